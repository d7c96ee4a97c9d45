// rotor_rub_run: the headless runner. No master, no ROS: a scene file in,
// a CSV of samples and a JSON summary out. See docs/tools.md.
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
#include <vector>

#include "cli_options.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "rotor_rub_sim/core/solver_registry.hpp"
#include "rotor_rub_sim/core/trajectory_compare.hpp"
#include "run_output.hpp"

namespace {

using namespace rotor_rub;
namespace cli = rotor_rub::cli;

constexpr int kExitBadInput = 2;
constexpr int kExitOutput = 6;

[[noreturn]] void bad_input(const std::string& msg) {
  std::cerr << "rotor_rub_run: " << msg << "\n";
  std::exit(kExitBadInput);
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene_path, csv_path, summary_path, keyphasor_path, probes_path, shaft_path, method, integrator, rtol,
      atol, rate;
  std::vector<std::string> sets;
  bool quiet = false, list_keys = false, list_solvers = false;
  CLI::App app(
      "The headless runner: runs a scene on the core (no master, no ROS) and writes its samples (CSV) "
      "and a summary (JSON).",
      "rotor_rub_run");
  cli::add_scene_options(app, scene_path, sets, "the scene file: flat YAML of scene keys (see --list-keys); required",
                         "sets any scene key, repeatable; --method, --integrator, --rtol, --atol and --rate win over "
                         "--set of the same key");
  app.add_option("--method", method, cli::scene_key_description("method"))
      ->type_name("NAME")
      ->check(cli::scene_key("method"));
  app.add_option("--integrator", integrator, cli::scene_key_description("integrator"))
      ->type_name("NAME")
      ->check(cli::scene_key("integrator"));
  app.add_option("--rtol", rtol, cli::scene_key_description("rtol"))->type_name("R")->check(cli::scene_key("rtol"));
  app.add_option("--atol", atol, cli::scene_key_description("atol"))->type_name("A")->check(cli::scene_key("atol"));
  app.add_option("--rate", rate, cli::scene_key_description("output_rate_hz"))
      ->type_name("HZ")
      ->check(cli::scene_key("output_rate_hz"));
  app.add_option("--csv", csv_path, "write the samples to this CSV file (one row per sample at t = k / rate)")
      ->type_name("FILE");
  app.add_option("--summary", summary_path, "write the JSON summary (status, events, stats) to this file")
      ->type_name("FILE");
  app.add_option("--keyphasor", keyphasor_path,
                 "write the keyphasor's marks (t, revolution, speed: once per revolution, at the spin angle 2 pi k, "
                 "from the dense output) to this CSV file")
      ->type_name("FILE");
  app.add_option("--probes", probes_path,
                 "write the X/Y proximity probes' signals (t, x_V, y_V, x_m, y_m at probe_rate_hz, which must be > 0) "
                 "to this CSV file")
      ->type_name("FILE");
  app.add_option("--shaft", shaft_path,
                 "write a flexible rotor's deflected shaft (needs rotor_file; a row per node and sample, on the "
                 "samples' grid: t, node, z_m, x_m, y_m, the node's position along the shaft and its lateral "
                 "displacement [m]) to this CSV file")
      ->type_name("FILE");
  app.add_flag("--quiet", quiet, "no summary line on stdout");
  app.add_flag("--list-keys", list_keys, "print every scene key with its default, accepted range and meaning; exit");
  app.add_flag("--list-solvers", list_solvers,
               "print each method's integrators, the one integrator auto picks, and when to use each; exit");
  app.footer(
      "Exit status: 0 ok; 2 bad input (usage, scene); 3 stalled; 4 diverged; 5 not converged; 6 output file error;\n"
      "7 timed out; 8 invariant violated. See docs/tools.md.");
  cli::parse_or_exit(app, argc, argv);
  if (list_keys) {
    for (const auto& k : core::scene_keys()) {
      std::printf("%-34s default %-10s accepted %s\n    %s%s\n", k.key.c_str(), k.default_value.c_str(),
                  k.accepted.c_str(), k.description.c_str(), k.live ? " (live: may change while running)" : "");
    }
    return 0;
  }
  if (list_solvers) {
    std::printf("method     integrator          auto picks it  when to use it\n%s", core::solver_table_text().c_str());
    return 0;
  }
  if (scene_path.empty()) cli::usage_error(app, "--scene is required");
  std::map<std::string, std::string> overrides = cli::scene_overrides(sets);
  if (!method.empty()) overrides["method"] = method;
  if (!integrator.empty()) overrides["integrator"] = integrator;
  if (!rtol.empty()) overrides["rtol"] = rtol;
  if (!atol.empty()) overrides["atol"] = atol;
  if (!rate.empty()) overrides["output_rate_hz"] = rate;

  core::Scene scene;
  try {
    scene = core::load_scene(scene_path, overrides);
  } catch (const std::exception& e) {
    bad_input(e.what());
  }

  if (!probes_path.empty() && !(scene.probes.rate_hz > 0.0)) {
    bad_input("--probes needs probe_rate_hz > 0 (scene key probe_rate_hz is 0: no probe signals); accepted: (0, 1e7]");
  }
  if (!shaft_path.empty() && core::rotor_kind(scene) == core::RotorKind::kJeffcott) {
    bad_input(
        "--shaft needs a flexible rotor (scene key rotor_file is empty: the Jeffcott has no shaft); accepted: "
        "a scene with a rotor_file");
  }
  tools::RunRecorder recorder(!csv_path.empty(), !keyphasor_path.empty(), probes_path.empty() ? nullptr : &scene.probes,
                              shaft_path.empty() ? 0.0 : scene.output_rate_hz);
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
  auto write_file = [&](const std::string& path, const char* what, auto&& write) {
    if (path.empty()) return;
    std::ofstream os(path);
    write(os);
    if (!os) {
      std::cerr << "rotor_rub_run: cannot write " << what << " '" << path << "'\n";
      status = kExitOutput;
    }
  };
  write_file(keyphasor_path, "keyphasor CSV",
             [&](std::ostream& os) { tools::write_keyphasor_csv(os, recorder.marks); });
  write_file(probes_path, "probes CSV",
             [&](std::ostream& os) { tools::write_probes_csv(os, recorder.probe_readings); });
  write_file(shaft_path, "shaft CSV",
             [&](std::ostream& os) { tools::write_shaft_csv(os, recorder.shaft, sim.shaft_node_z_m()); });
  if (!summary_path.empty()) {
    std::ofstream os(summary_path);
    tools::write_summary_json(
        os, {scene_path, &scene, &recorder, st, &sim.failure(), sim.time(), sim.contact_point(), sim.reduction()});
    if (!os) {
      std::cerr << "rotor_rub_run: cannot write summary '" << summary_path << "'\n";
      status = kExitOutput;
    }
  }
  if (!quiet && sim.reduction().planar_modes > 0)
    std::printf("rotor: %s\n", core::to_string(sim.reduction().planar_modes, sim.reduction().truncation).c_str());
  if (!quiet) {
    const auto sustained = core::longest_contact(recorder.events, sim.time());
    std::printf(
        "%-9s %-11s rtol %-7.0e first contact %9.6f s  sustained contact %9.6f .. %9.6f s  last contact end %9.6f s"
        "  max orbit %.6e m  max F_n %8.4f N  steps %7ld (+%ld rej)  rhs %8ld  iter %8ld  wall %8.3f ms\n",
        core::to_string(scene.solver.method), core::to_string(sim.scene().solver.integrator), scene.solver.rtol,
        core::first_contact_s(recorder.events), sustained.first, sustained.second,
        core::last_contact_end_s(recorder.events), recorder.max_orbit_m, recorder.max_normal_force_N, st.steps,
        st.rejected_steps, st.rhs_evals, st.root_iterations, st.wall_time_s * 1e3);
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
