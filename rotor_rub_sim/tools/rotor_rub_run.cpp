// rotor_rub_run: the headless runner. No master, no ROS: a scene file in,
// a CSV of samples and a JSON summary out. See README "Headless runner".
//
// Exit status: 0 ok; 2 bad input (usage, scene); 3 stalled; 4 diverged;
// 5 not converged; 6 output file error; 7 timed out; 8 invariant violated.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <string>

#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "rotor_rub_sim/core/trajectory_compare.hpp"
#include "run_output.hpp"

namespace {

using namespace rotor_rub;

constexpr int kExitBadInput = 2;
constexpr int kExitOutput = 6;

const char* kUsage =
    "usage: rotor_rub_run --scene FILE [--method penalty|switching|iteration] [--rtol R] [--atol A]\n"
    "                     [--set key=value]... [--rate HZ] [--csv FILE] [--summary FILE] [--quiet]\n"
    "       rotor_rub_run --list-keys\n";

[[noreturn]] void bad_input(const std::string& msg) {
  std::cerr << "rotor_rub_run: " << msg << "\n";
  std::exit(kExitBadInput);
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene_path, csv_path, summary_path;
  std::map<std::string, std::string> overrides;
  bool quiet = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](const char* flag) -> std::string {
      if (i + 1 >= argc) bad_input(std::string(flag) + " needs a value\n" + kUsage);
      return argv[++i];
    };
    if (a == "--scene")
      scene_path = value("--scene");
    else if (a == "--method")
      overrides["method"] = value("--method");
    else if (a == "--rtol")
      overrides["rtol"] = value("--rtol");
    else if (a == "--atol")
      overrides["atol"] = value("--atol");
    else if (a == "--rate")
      overrides["output_rate_hz"] = value("--rate");
    else if (a == "--csv")
      csv_path = value("--csv");
    else if (a == "--summary")
      summary_path = value("--summary");
    else if (a == "--quiet")
      quiet = true;
    else if (a == "--set") {
      const std::string kv = value("--set");
      const auto eq = kv.find('=');
      if (eq == std::string::npos || eq == 0) bad_input("--set expects key=value, got '" + kv + "'");
      overrides[kv.substr(0, eq)] = kv.substr(eq + 1);
    } else if (a == "--list-keys") {
      for (const auto& k : core::scene_keys()) {
        std::printf("%-34s default %-10s accepted %s\n    %s\n", k.key.c_str(), k.default_value.c_str(),
                    k.accepted.c_str(), k.description.c_str());
      }
      return 0;
    } else if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      return 0;
    } else {
      bad_input("unknown option '" + a + "'\n" + kUsage);
    }
  }
  if (scene_path.empty()) bad_input(std::string("--scene is required\n") + kUsage);

  core::Scene scene;
  try {
    scene = core::load_scene(scene_path, overrides);
  } catch (const std::exception& e) {
    bad_input(e.what());
  }

  tools::RunRecorder recorder(!csv_path.empty());
  core::Simulation sim(scene);
  sim.advance_to(scene.end_time_s, recorder);
  const core::RunStats& st = sim.stats();

  // Outputs keep everything computed before a failure.
  int status = 0;
  if (!csv_path.empty()) {
    std::ofstream os(csv_path);
    tools::write_csv(os, recorder.samples);
    if (!os) {
      std::cerr << "rotor_rub_run: cannot write CSV '" << csv_path << "'\n";
      status = kExitOutput;
    }
  }
  if (!summary_path.empty()) {
    std::ofstream os(summary_path);
    tools::write_summary_json(os, {scene_path, &scene, &recorder, st, &sim.failure()});
    if (!os) {
      std::cerr << "rotor_rub_run: cannot write summary '" << summary_path << "'\n";
      status = kExitOutput;
    }
  }
  if (!quiet) {
    const auto sustained = core::longest_contact(recorder.events);
    std::printf(
        "%-9s rtol %-7.0e first contact %9.6f s  sustained contact %9.6f .. %9.6f s  last contact end %9.6f s"
        "  max orbit %.6e m  max F_n %8.4f N  steps %7ld (+%ld rej)  rhs %8ld  iter %8ld  wall %8.3f ms\n",
        core::to_string(scene.solver.method), scene.solver.rtol, core::first_contact_s(recorder.events),
        sustained.first, sustained.second, core::last_contact_end_s(recorder.events), recorder.max_orbit_m,
        recorder.max_normal_force_N, st.steps, st.rejected_steps, st.rhs_evals, st.root_iterations,
        st.wall_time_s * 1e3);
  }
  if (const auto& f = sim.failure()) {
    const core::Sample& last = recorder.last_sample;
    std::fprintf(stderr, "rotor_rub_run: %s at t = %.9g s: %s (last sample t = %.9g s, x_r = %.9g m, y_r = %.9g m)\n",
                 core::to_string(f->failure_class), f->time_s, f->message.c_str(), last.t_s, last.kin.rotor_pos.x(),
                 last.kin.rotor_pos.y());
    return core::exit_status(f->failure_class);
  }
  return status;
}
