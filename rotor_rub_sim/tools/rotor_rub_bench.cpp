// rotor_rub_bench: speed against accuracy on a scene (default: the paper's
// run-up), per method and tolerance, beside the paper's Table 2.
//   rotor_rub_bench [--scene FILE] [--repeats N] [--error-rate HZ] [--quick]
// (--help describes them; the default scene is the package's, from any
// directory).
// Wall time: median of N runs of the whole scene as the headless runner does
// it (samples at the scene's output rate, none stored). Error: a separate run
// sampled at --error-rate against the reference (switching, rtol 1e-12).
// Shares of time: a third, profiled run (clock reads around every derivative
// evaluation and force iteration inflate its total, not its shares much).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "cli_options.hpp"
#include "package_paths.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "rotor_rub_sim/core/trajectory_compare.hpp"

namespace {

using namespace rotor_rub::core;

struct Collect : SimulationObserver {
  std::vector<Sample> samples;
  std::vector<ContactEvent> events;
  void on_sample(const Sample& s) override { samples.push_back(s); }
  void on_event(const ContactEvent& e) override { events.push_back(e); }
};

struct Case {
  Method method;
  double rtol, atol;
  Integrator integrator = Integrator::kDopri5;
};

Scene with(const Scene& base, const Case& c) {
  Scene s = base;
  s.solver.method = c.method;
  s.solver.rtol = c.rtol;
  s.solver.atol = c.atol;
  s.solver.integrator = c.integrator;
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  namespace cli = rotor_rub::tools::cli;
  std::string scene_path;
  int repeats = 5;
  double error_rate_hz = 10000.0;
  bool quick = false;
  CLI::App app(
      "Speed against accuracy on a scene, per method and tolerance, beside the paper's Table 2. Wall time: median "
      "of the timed runs; error: a run sampled at --error-rate against the reference (switching, rtol 1e-12).",
      "rotor_rub_bench");
  app.add_option("--scene", scene_path,
                 "the scene file (default: the package's config/paper_runup.yaml, found from any directory)")
      ->type_name("FILE")
      ->check(cli::existing_file());
  app.add_option("--repeats", repeats, "timed runs per case; the wall time is their median [runs]")
      ->type_name("N")
      ->check(cli::integer_in(1, 1000))
      ->capture_default_str();
  app.add_option("--error-rate", error_rate_hz,
                 "sample rate of the runs compared with the reference, in simulated time [Hz]")
      ->type_name("HZ")
      ->check(cli::number_in(0, 1e7, true))
      ->capture_default_str();
  app.add_flag("--quick", quick, "two tolerances per method (1e-3 and 1e-6) instead of six");
  app.footer("Exit status: 0 done; 1 the reference run failed; 2 bad input (usage, scene).");
  cli::parse_or_exit(app, argc, argv);
  if (scene_path.empty()) {
    try {
      scene_path = rotor_rub::tools::find_package_file("config/paper_runup.yaml");
    } catch (const std::exception& e) {
      std::cerr << "rotor_rub_bench: no default scene: " << e.what() << "; give --scene FILE\n";
      return 2;
    }
  }
  Scene base;
  try {
    base = load_scene(scene_path);
  } catch (const std::exception& e) {
    std::cerr << "rotor_rub_bench: " << e.what() << "\n";
    return 2;
  }

  Scene ref_scene = with(base, {Method::kSwitching, 1e-12, 1e-15});
  ref_scene.output_rate_hz = error_rate_hz;
  Collect ref;
  const RunResult ref_result = run_scene(ref_scene, ref);
  if (ref_result.failure) {
    std::cerr << "rotor_rub_bench: reference failed: " << ref_result.failure->message << "\n";
    return 1;
  }
  const auto ref_contact = longest_contact(ref.events);
  std::printf("scene %s; reference: switching rtol 1e-12 atol 1e-15, %ld steps\n", scene_path.c_str(),
              ref_result.stats.steps);
  std::printf("reference: first contact %.9f s, sustained contact %.9f .. %.9f s, last contact ends %.9f s\n\n",
              first_contact_s(ref.events), ref_contact.first, ref_contact.second, last_contact_end_s(ref.events));

  std::vector<Case> cases;
  const std::vector<std::pair<double, double>> tolerances =
      quick ? std::vector<std::pair<double, double>>{{1e-3, 1e-6}, {1e-6, 1e-9}}
            : std::vector<std::pair<double, double>>{{1e-3, 1e-6},  {1e-5, 1e-8},  {1e-6, 1e-9},
                                                     {1e-7, 1e-10}, {1e-8, 1e-11}, {1e-9, 1e-12}};
  for (Method m : {Method::kSwitching, Method::kIteration, Method::kPenalty}) {
    for (const auto& [r, a] : tolerances) cases.push_back({m, r, a});
  }
  for (const auto& [r, a] : tolerances) {
    if (r >= 1e-7) cases.push_back({Method::kPenalty, r, a, Integrator::kRosenbrock4});
  }

  std::printf("%-9s %-11s %7s %7s | %9s %8s %7s %8s %9s | %5s %5s | %9s %9s %9s | %9s\n", "method", "integrator",
              "rtol", "atol", "wall[ms]", "steps", "rej", "rhs", "iter", "rhs%", "iter%", "max|dx_r|", "rms dx_r",
              "max|dr_s|", "dt_first");
  for (const Case& c : cases) {
    const Scene s = with(base, c);
    std::vector<double> walls;
    RunResult timed;
    for (int r = 0; r < repeats; ++r) {
      SimulationObserver none;
      timed = run_scene(s, none);
      walls.push_back(timed.stats.wall_time_s);
    }
    std::nth_element(walls.begin(), walls.begin() + walls.size() / 2, walls.end());
    const double wall_ms = walls[walls.size() / 2] * 1e3;

    Scene es = s;
    es.output_rate_hz = error_rate_hz;
    Collect run;
    const RunResult er = run_scene(es, run);
    const TrajectoryError err = compare_trajectories(run.samples, ref.samples);

    Scene ps = s;
    ps.solver.profile_cost = true;
    SimulationObserver none;
    const RunResult prof = run_scene(ps, none);
    const double pw = prof.stats.wall_time_s;
    const double rhs_share = 100.0 * (prof.stats.rhs_time_s - prof.stats.iteration_time_s) / pw;
    const double iter_share = 100.0 * prof.stats.iteration_time_s / pw;

    const char* status = timed.failure ? to_string(timed.failure->failure_class) : "";
    std::printf("%-9s %-11s %7.0e %7.0e | %9.3f %8ld %7ld %8ld %9ld | %5.1f %5.1f | %9.2e %9.2e %9.2e | %9.2e %s\n",
                to_string(c.method), to_string(c.integrator), c.rtol, c.atol, wall_ms, timed.stats.steps,
                timed.stats.rejected_steps, timed.stats.rhs_evals, timed.stats.root_iterations, rhs_share, iter_share,
                err.max_rotor_x_m, err.rms_rotor_x_m, err.max_stator_m,
                std::abs(first_contact_s(run.events) - first_contact_s(ref.events)), status);
    (void)er;
  }
  std::printf(
      "\npaper (MATLAB ode45, rtol 1e-3, atol 1e-6): penalty 1123 s, 90459 steps, rhs 62%%, iter 0%%; "
      "switching 45 s, 1857 steps, 64%%, 1%%; iteration 1050 s, 8040 steps, 19%%, 65%%\n");
  return 0;
}
