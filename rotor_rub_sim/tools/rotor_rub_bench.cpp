// rotor_rub_bench: speed against accuracy on a scene (default: the paper's
// run-up), per method and tolerance, beside the paper's Table 2 and beside
// the switching method on SUNDIALS CVODE (cvode_switching.hpp).
//   rotor_rub_bench [--scene FILE] [--repeats N] [--error-rate HZ] [--quick]
//                   [--methods LIST] [--csv FILE]
// (--help describes them; the default scene is the package's, from any
// directory).
// Wall time: median of N runs of the whole scene as the headless runner does
// it (samples at the scene's output rate, none stored; CVODE's runs make no
// output at all). Error: a separate run sampled at --error-rate against the
// reference (switching, rtol 1e-12). Shares of time: a third, profiled run
// (clock reads around every derivative evaluation, force iteration, event
// scan, restart and output inflate its total, not its shares much).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "cli_options.hpp"
#ifdef ROTOR_RUB_HAVE_CVODE
#include "cvode_switching.hpp"
#endif
#include "package_paths.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "rotor_rub_sim/core/solver_registry.hpp"
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
  Integrator integrator = Integrator::kAuto;
};

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// One line of the table (and of --csv). Shares [%] are of a separate
// profiled run's wall time: rhs (derivatives, iteration excluded), iter (the
// normal force iteration), event (scan, location, impact law), restart
// (entering the next regime), out (samples and their checks), step (the
// rest: stages, error control, step-size control). CVODE rows have none.
struct Row {
  Row(std::string m, std::string i, double r, double a)
      : method(std::move(m)), integrator(std::move(i)), rtol(r), atol(a) {}
  std::string method, integrator;
  double rtol = 0.0, atol = 0.0;
  double wall_ms = 0.0;
  double quiet_wall_ms = NAN;  // ours without output (two samples), as CVODE is timed
  long steps = 0, rejected = 0, rhs = 0, iterations = 0, restarts = 0;
  double rhs_pct = NAN, iter_pct = NAN, event_pct = NAN, restart_pct = NAN, output_pct = NAN;
  double max_err_m = NAN, rms_err_m = NAN, max_stator_err_m = NAN, first_contact_err_s = NAN;
  std::string status;

  double step_pct() const { return 100.0 - rhs_pct - iter_pct - event_pct - restart_pct - output_pct; }
  // The errors of a run sampled like the reference; a run that delivered
  // fewer samples (it failed on the way) is failed, whatever its prefix.
  void set_errors(const TrajectoryError& e, double first_contact, double ref_first_contact, std::size_t samples,
                  std::size_t ref_samples, const char* failure) {
    if (failure) status = failure;
    if (samples != ref_samples && status == "ok") status = "short";
    max_err_m = e.max_rotor_m;
    rms_err_m = e.rms_rotor_x_m;
    max_stator_err_m = e.max_stator_m;
    first_contact_err_s = std::abs(first_contact - ref_first_contact);
  }
  void print() const {
    std::printf(
        "%-9s %-11s %7.0e %7.0e | %9.3f %9.3f %8ld %7ld %8ld %9ld %5ld | %5.1f %5.1f %5.1f %5.1f %5.1f %5.1f | %9.2e "
        "%9.2e "
        "%9.2e | %9.2e %s\n",
        method.c_str(), integrator.c_str(), rtol, atol, wall_ms, quiet_wall_ms, steps, rejected, rhs, iterations,
        restarts, rhs_pct, iter_pct, event_pct, restart_pct, output_pct, step_pct(), max_err_m, rms_err_m,
        max_stator_err_m, first_contact_err_s, status == "ok" ? "" : status.c_str());
    std::fflush(stdout);
  }
};

void print_header() {
  std::printf("%-9s %-11s %7s %7s | %9s %9s %8s %7s %8s %9s %5s | %5s %5s %5s %5s %5s %5s | %9s %9s %9s | %9s\n",
              "method", "integrator", "rtol", "atol", "wall[ms]", "quiet[ms]", "steps", "rej", "rhs", "iter", "rst",
              "rhs%", "iter%", "evt%", "rst%", "out%", "step%", "max|dr_r|", "rms dx_r", "max|dr_s|", "dt_first");
}

// Per error bound: the cheapest completed row of each method and integrator
// within it (by the quiet time), and CVODE's cheapest against ours, the
// ratio measured in this run.
void print_cheapest(const std::vector<Row>& rows) {
  for (const double bound : {1e-5, 1e-6, 1e-7}) {
    std::printf("\ncheapest within %.0e m (max |r_r - r_r,ref|): rtol, wall with samples / quiet, error\n", bound);
    const Row* ours = nullptr;
    const Row* cvode = nullptr;
    std::vector<std::string> seen;
    for (const Row& r : rows) {
      const std::string key = r.method + " " + r.integrator;
      if (std::find(seen.begin(), seen.end(), key) != seen.end()) continue;
      seen.push_back(key);
      const Row* best = nullptr;
      for (const Row& q : rows) {
        if (q.method + " " + q.integrator != key || q.status != "ok" || !(q.max_err_m <= bound)) continue;
        if (!best || q.quiet_wall_ms < best->quiet_wall_ms) best = &q;
      }
      if (!best) {
        std::printf("  %-22s none\n", key.c_str());
        continue;
      }
      std::printf("  %-22s rtol %7.0e  %9.3f / %9.3f ms  %9.2e m\n", key.c_str(), best->rtol, best->wall_ms,
                  best->quiet_wall_ms, best->max_err_m);
      const Row*& slot = r.method == "cvode" ? cvode : ours;
      if (!slot || best->quiet_wall_ms < slot->quiet_wall_ms) slot = best;
    }
    if (ours && cvode) {
      std::printf("  CVODE (%s) / ours (%s %s): %.1fx both quiet; %.1fx against ours with samples\n",
                  cvode->integrator.c_str(), ours->method.c_str(), ours->integrator.c_str(),
                  cvode->quiet_wall_ms / ours->quiet_wall_ms, cvode->quiet_wall_ms / ours->wall_ms);
    }
  }
}

bool write_csv(const std::string& path, const std::vector<Row>& rows) {
  std::ofstream f(path);
  f << "method,integrator,rtol,atol,status,wall_time_s,quiet_wall_time_s,steps,rejected_steps,rhs_evals,root_"
       "iterations,restarts,"
       "rhs_share,iteration_share,event_share,restart_share,output_share,max_rotor_err_m,rms_rotor_x_err_m,"
       "max_stator_err_m,first_contact_err_s\n";
  f.precision(6);
  for (const Row& r : rows) {
    f << r.method << ',' << r.integrator << ',' << r.rtol << ',' << r.atol << ',' << r.status << ',' << r.wall_ms * 1e-3
      << ',' << r.quiet_wall_ms * 1e-3 << ',' << r.steps << ',' << r.rejected << ',' << r.rhs << ',' << r.iterations
      << ',' << r.restarts << ',' << r.rhs_pct / 100 << ',' << r.iter_pct / 100 << ',' << r.event_pct / 100 << ','
      << r.restart_pct / 100 << ',' << r.output_pct / 100 << ',' << r.max_err_m << ',' << r.rms_err_m << ','
      << r.max_stator_err_m << ',' << r.first_contact_err_s << '\n';
  }
  return static_cast<bool>(f);
}

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
  namespace cli = rotor_rub::cli;
  std::string scene_path;
  int repeats = 5;
  double error_rate_hz = 10000.0;
  bool quick = false;
  std::string csv_path;
  // The rows: every method on each of its registry's integrators but rk4 (its
  // fixed step has no tolerance to sweep), switching first (the headline
  // rows), the rigid methods before the penalty one, then CVODE. A method
  // added to kAllMethods fails the size check until it has its place here.
  constexpr std::array<Method, 3> method_order{Method::kSwitching, Method::kIteration, Method::kPenalty};
  static_assert(method_order.size() == kAllMethods.size(), "rotor_rub_bench: a method without its rows");
  std::vector<std::string> row_names;
  std::string methods_help = "which rows:";
  for (const Method m : method_order) {
    std::string integrators;
    for (const SolverEntry& e : solver_registry()) {
      if (e.method != m || e.integrator == Integrator::kRk4) continue;
      integrators += (integrators.empty() ? "" : ", ") + std::string(to_string(e.integrator));
    }
    row_names.push_back(to_string(m));
    methods_help += " " + row_names.back() + " (" + integrators + "),";
  }
  row_names.push_back("cvode");
  methods_help += " cvode (the switching method on SUNDIALS CVODE, Adams and BDF)";
  std::vector<std::string> methods = row_names;
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
  app.add_flag("--quick", quick,
               "two tolerances per method (1e-3 and 1e-6) instead of ten (1e-3, 1e-4; 1e-5 to 1e-8 by half "
               "decades; 1e-9)");
  app.add_option("--methods", methods, methods_help)
      ->type_name("LIST")
      ->delimiter(',')
      ->check(CLI::IsMember(row_names))
      ->capture_default_str();
  app.add_option("--csv", csv_path, "also write the table to this CSV file (scripts/plot_charts.py reads it)")
      ->type_name("FILE");
  app.footer("Exit status: 0 done; 1 the reference run failed; 2 bad input (usage, scene).");
  cli::parse_or_exit(app, argc, argv);
  if (scene_path.empty()) {
    try {
      scene_path = rotor_rub::cli::find_package_file("config/paper_runup.yaml");
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

  Scene ref_scene = with(base, {Method::kSwitching, 1e-12, 1e-15, Integrator::kDopri5});
  ref_scene.output_rate_hz = error_rate_hz;
  Collect ref;
  const RunResult ref_result = run_scene(ref_scene, ref);
  if (ref_result.failure) {
    std::cerr << "rotor_rub_bench: reference failed: " << ref_result.failure->message << "\n";
    return 1;
  }
  const auto ref_contact = longest_contact(ref.events);
  const double ref_first_contact_s = first_contact_s(ref.events);
  std::printf("scene %s; reference: switching rtol 1e-12 atol 1e-15, %ld steps\n", scene_path.c_str(),
              ref_result.stats.steps);
  std::printf("reference: first contact %.9f s, sustained contact %.9f .. %.9f s, last contact ends %.9f s\n\n",
              first_contact_s(ref.events), ref_contact.first, ref_contact.second, last_contact_end_s(ref.events));

  std::vector<Case> cases;
  const std::vector<std::pair<double, double>> tolerances =
      quick ? std::vector<std::pair<double, double>>{{1e-3, 1e-6}, {1e-6, 1e-9}}
            : std::vector<std::pair<double, double>>{{1e-3, 1e-6},  {1e-4, 1e-7},  {1e-5, 1e-8},  {3e-6, 3e-9},
                                                     {1e-6, 1e-9},  {3e-7, 3e-10}, {1e-7, 1e-10}, {3e-8, 3e-11},
                                                     {1e-8, 1e-11}, {1e-9, 1e-12}};
  auto wanted = [&methods](const char* m) { return std::find(methods.begin(), methods.end(), m) != methods.end(); };
  for (const Method m : method_order) {
    if (!wanted(to_string(m))) continue;
    for (const SolverEntry& e : solver_registry()) {
      if (e.method != m || e.integrator == Integrator::kRk4) continue;
      for (const auto& [r, a] : tolerances) {
        // A pair the scene's validation refuses is named and left out.
        try {
          validate_scene(with(base, {m, r, a, e.integrator}));
        } catch (const SceneError& err) {
          std::printf("%s %s rtol %g: not run: %s\n", to_string(m), to_string(e.integrator), r, err.what());
          continue;
        }
        cases.push_back({m, r, a, e.integrator});
      }
    }
  }

  std::vector<Row> rows;
  print_header();
  for (const Case& c : cases) {
    const Scene s = with(base, c);
    Row row{to_string(c.method), to_string(c.integrator), c.rtol, c.atol};
    std::vector<double> walls;
    RunResult timed;
    for (int r = 0; r < repeats; ++r) {
      SimulationObserver none;
      timed = run_scene(s, none);
      walls.push_back(timed.stats.wall_time_s);
    }
    row.wall_ms = median(walls) * 1e3;
    Scene quiet = s;
    quiet.output_rate_hz = 1.0 / s.end_time_s;  // a sample at 0 and at the end
    walls.clear();
    for (int r = 0; r < repeats; ++r) {
      SimulationObserver none;
      walls.push_back(run_scene(quiet, none).stats.wall_time_s);
    }
    row.quiet_wall_ms = median(walls) * 1e3;
    row.steps = timed.stats.steps;
    row.rejected = timed.stats.rejected_steps;
    row.rhs = timed.stats.rhs_evals;
    row.iterations = timed.stats.root_iterations;
    row.restarts = timed.stats.restarts;
    row.status = timed.failure ? to_string(timed.failure->failure_class) : "ok";

    Scene es = s;
    es.output_rate_hz = error_rate_hz;
    Collect run;
    const RunResult er = run_scene(es, run);
    row.set_errors(compare_trajectories(run.samples, ref.samples), first_contact_s(run.events), ref_first_contact_s,
                   run.samples.size(), ref.samples.size(), er.failure ? to_string(er.failure->failure_class) : nullptr);

    Scene ps = s;
    ps.solver.profile_cost = true;
    SimulationObserver none;
    const RunStats pst = run_scene(ps, none).stats;
    const double pw = pst.wall_time_s / 100.0;
    row.rhs_pct = (pst.rhs_time_s - pst.iteration_time_s) / pw;
    row.iter_pct = pst.iteration_time_s / pw;
    row.event_pct = pst.event_time_s / pw;
    row.restart_pct = pst.restart_time_s / pw;
    row.output_pct = pst.output_time_s / pw;
    row.print();
    rows.push_back(row);
  }

  // The same model on SUNDIALS CVODE (tools/cvode_switching.hpp), at the same
  // tolerances, timed without output; its error from a run sampled like ours.
#ifndef ROTOR_RUB_HAVE_CVODE
  if (wanted("cvode")) std::printf("cvode: not built (SUNDIALS CVODE, libsundials-dev, was missing at build time)\n");
#else
  if (wanted("cvode")) {
    for (const bool adams : {true, false}) {
      for (const auto& [r, a] : tolerances) {
        const Scene s = with(base, {Method::kSwitching, r, a});
        const rotor_rub::tools::CvodeOptions options{adams};
        Row row{"cvode", adams ? "adams" : "bdf", r, a};
        std::vector<double> walls;
        rotor_rub::tools::CvodeRun timed;
        for (int k = 0; k < repeats; ++k) {
          timed = rotor_rub::tools::run_cvode_switching(s, 0.0, options);
          walls.push_back(timed.wall_time_s);
        }
        row.wall_ms = row.quiet_wall_ms = median(walls) * 1e3;
        row.steps = timed.steps;
        row.rejected = timed.error_test_failures + timed.nonlinear_failures;
        row.rhs = timed.rhs_evals;
        row.iterations = timed.root_evals;
        row.restarts = timed.reinits;
        row.status = timed.failure ? "failed" : "ok";
        const auto er = rotor_rub::tools::run_cvode_switching(s, error_rate_hz, options);
        row.set_errors(compare_trajectories(er.samples, ref.samples), first_contact_s(er.events_found),
                       ref_first_contact_s, er.samples.size(), ref.samples.size(), er.failure ? "failed" : nullptr);
        row.print();
        if (timed.failure) std::printf("  cvode: %s\n", timed.failure->c_str());
        rows.push_back(row);
      }
    }
  }
#endif
  print_cheapest(rows);
  if (!csv_path.empty() && !write_csv(csv_path, rows)) {
    std::cerr << "rotor_rub_bench: cannot write --csv " << csv_path << "\n";
    return 2;
  }
  std::printf(
      "\npaper (MATLAB ode45, rtol 1e-3, atol 1e-6): penalty 1123 s, 90459 steps, rhs 62%%, iter 0%%; "
      "switching 45 s, 1857 steps, 64%%, 1%%; iteration 1050 s, 8040 steps, 19%%, 65%%\n");
  return 0;
}
