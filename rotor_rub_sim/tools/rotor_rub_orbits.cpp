// rotor_rub_orbits: the periodic orbit a Jeffcott scene settles into at a
// constant speed, and whether it holds (periodic_orbit.hpp): its events
// over a period, its Floquet multipliers from the exact monodromy, stable or
// not; with --continue, its branch over a speed range in both directions by
// pseudo-arclength continuation (orbit_continuation.hpp), with its folds,
// period doublings and Neimark-Sacker points, and the branches of twice the
// period born at the doublings (--doublings levels deep). The orbit starts
// from the scene's event-driven flow (the switching method's physics) run
// from rest for --settle-periods periods, or from a run's sample
// (--from-run, --at: an orbit the run's history settled on), then Newton on
// the shooting residual. The contact is the rigid one (the scene's method switching or
// iteration), under the prescribed drive (docs/periodic_orbits.md).
//
// Exit status: 0 ok (a branch's end is reported, not an error); 2 bad input
// (usage, scene, a scene it does not model); 3 no periodic orbit at the
// speed (Newton does not converge, the orbit grazes or chatters).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "cli_options.hpp"
#include "rotor_rub_sim/core/orbit_continuation.hpp"
#include "rotor_rub_sim/core/periodic_orbit.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/turning_orbit.hpp"
#include "run_comparison.hpp"

namespace {

using namespace rotor_rub;

[[noreturn]] void bad_input(const std::string& msg) {
  std::cerr << "rotor_rub_orbits: " << msg << "\n";
  std::exit(2);
}

// The least period of an orbit of n forcing periods, in forcing periods: the
// smallest divisor d of n whose shot returns to the state (to kSamePoint of
// C and C w).
int least_period(const core::ModelParameters& p, const core::PeriodicOrbit& o) {
  constexpr double kSamePoint = 1e-7;
  const double w = o.speed_rad_per_s, t0 = o.section_angle_rad / w, period = 2.0 * M_PI / w;
  const int v = static_cast<int>(o.state.size()) / 2;
  for (int d = 1; d < o.periods; ++d) {
    if (o.periods % d != 0) continue;
    const Eigen::VectorXd back = core::orbit_flow(p, w, o.state, t0, t0 + d * period).state - o.state;
    const double off = std::max(back.head(v).cwiseAbs().maxCoeff() / p.clearance_m,
                                back.tail(v).cwiseAbs().maxCoeff() / (p.clearance_m * w));
    if (off < kSamePoint) return d;
  }
  return o.periods;
}

// A largest multiplier whose modulus is this close to 1 is neutral to the
// monodromy's accuracy (1e-10 on the examples, 2e-8 on a fast rolling whose
// field's Jacobian is a difference): a family of orbits (a rolling whose
// R_r / C is an integer: OrbitsCli.StickingOrbits) or a bifurcation.
constexpr double kNeutral = 1e-6;

// The forcing periods scanned for a turning-frame orbit's repeating impacts
// (turning_orbit_guess).
constexpr int kTurningScan = 100;

void print_orbit(const core::ModelParameters& p, const core::PeriodicOrbit& o) {
  const bool neutral = std::abs(std::abs(o.multipliers.front()) - 1.0) < kNeutral;
  if (o.turning) {
    std::printf(
        "orbit at %.6f rad/s in the frame turning with the shaft: period T_r = %.12g s (%.6f forcing periods: "
        "quasi-periodic in the casing), %s, Newton %d iterations (residual %.2g of C); trivial multiplier 1 %+.1e "
        "(the flow's direction, left out below)\n",
        o.speed_rad_per_s, o.period_s, o.period_s * o.speed_rad_per_s / (2.0 * M_PI),
        neutral      ? "neutral"
        : o.stable() ? "stable"
                     : "unstable",
        o.newton_iterations, o.residual, o.trivial_multiplier - 1.0);
  } else {
    std::printf("orbit at %.6f rad/s: period %d T = %.9g s, %s, Newton %d iterations (residual %.2g of C)\n",
                o.speed_rad_per_s, o.periods, o.period_s,
                neutral      ? "neutral"
                : o.stable() ? "stable"
                             : "unstable",
                o.newton_iterations, o.residual);
  }
  if (neutral) {
    std::printf(
        "  note: its largest multiplier lies on the unit circle to %g: neutral (a family of orbits, as a rolling "
        "whose R_r / C is an integer, or a bifurcation)\n",
        kNeutral);
  }
  if (const int least = o.turning ? 1 : least_period(p, o); least < o.periods) {
    std::printf("  note: its least period is %d T: it is the orbit of --periods %d traced %d times\n", least, least,
                o.periods / least);
  }
  if (!o.stable() && !neutral) {
    std::printf(
        "  note: unstable, so no run stays on it: the run from rest settled elsewhere (a periodic orbit of "
        "more periods, --periods 2, 4, ...; or a motion that is not periodic)\n");
  }
  for (const core::OrbitEvent& e : o.events) {
    std::printf("  %-9s at t = %.9f s (spin angle %.4f rad)", core::to_string(e.kind), e.time_s,
                std::fmod(e.time_s * o.speed_rad_per_s, 2.0 * M_PI));
    if (core::is_impact(e.kind)) std::printf(", closing at %.6g m/s", e.normal_velocity_m_per_s);
    std::printf("\n");
  }
  if (o.events.empty()) {
    std::printf("  %s\n", !o.starts_in_contact ? "no contact"
                          : o.starts_in_stick  ? "on the bore throughout, sticking (rolling on it: dry whip)"
                                               : "on the bore throughout, sliding (the full rub)");
  }
  if (o.starts_in_contact) {
    std::printf("  (the section lies in a contact%s: the multipliers on the %s tangent space, %zu of them)\n",
                o.starts_in_stick ? ", sticking" : "", o.starts_in_stick ? "stick's" : "bore's", o.multipliers.size());
  }
  for (const std::complex<double>& mu : o.multipliers) {
    std::printf("  multiplier %+.9f %+.9fi  |mu| %.9f\n", mu.real(), mu.imag(), std::abs(mu));
  }
}

// One CSV row per keyphasor point of each orbit (rotor minus stator, as
// rotor_rub_bifurcation's Poincare points), in the orbit's order from the
// point of the largest radius (keyphasor 0; of an orbit on the bore, where
// every radius is C to the rounding, of the largest direction atan2(y, x)),
// which follows the same point along a branch wherever the section moves.
// A bifurcation's row has no verdict (stable empty: it is the boundary).
// Two keyphasor points' radii this close (relative) are the same: the bore's.
constexpr double kSameRadius = 1e-9;

void write_rows(std::ofstream& csv, int branch, const core::PeriodicOrbit& o, const char* bifurcation) {
  const int v = static_cast<int>(o.state.size()) / 2;
  const std::size_t n = o.keyphasor_states.size();
  std::vector<Eigen::Vector2d> rel(n);
  std::size_t first = 0;
  for (std::size_t k = 0; k < n; ++k) {
    rel[k] = o.keyphasor_states[k].head<2>();
    if (v == 4) rel[k] -= o.keyphasor_states[k].segment<2>(2);
    const double dr = rel[k].norm() - rel[first].norm();
    if (dr > kSameRadius * rel[first].norm() ||
        (std::abs(dr) <= kSameRadius * rel[first].norm() &&
         std::atan2(rel[k].y(), rel[k].x()) > std::atan2(rel[first].y(), rel[first].x()))) {
      first = k;
    }
  }
  const std::string verdict = *bifurcation != '\0' ? "" : (o.stable() ? "1" : "0");
  for (std::size_t j = 0; j < n; ++j) {
    const Eigen::Vector2d& r = rel[(first + j) % n];
    csv << branch << "," << o.periods << "," << o.speed_rad_per_s << "," << o.parameter << "," << j << "," << r.x()
        << "," << r.y() << "," << r.norm() << "," << std::abs(o.multipliers.front()) << "," << verdict << ","
        << o.events.size() << "," << bifurcation << "\n";
  }
}

// The start from a run (--from-run): the state of a rotor_rub_run CSV's
// sample at or after t_s, in the flow's layout, and its spin angle (the
// section). Exits 2 for a file that is not a run's, a time past its end, a
// speed other than the orbit's.
struct RunStart {
  Eigen::VectorXd state;
  double t_s = 0.0, angle_rad = 0.0;
};
RunStart start_from_run(const std::string& path, double t_s, const core::ModelParameters& p, double speed) {
  // The run's speed within this of --speed (relative): the same constant speed.
  constexpr double kSameSpeed = 1e-9;
  tools::RecordedRun run;
  try {
    run = tools::read_runner_csv(path, "");
  } catch (const std::exception& e) {
    bad_input("--from-run: " + std::string(e.what()));
  }
  const auto at =
      std::find_if(run.samples.begin(), run.samples.end(), [t_s](const core::Sample& s) { return s.t_s >= t_s; });
  if (at == run.samples.end()) {
    bad_input("--at " + core::exact_text(t_s) + ": past the run's last sample (t = " +
              (run.samples.empty() ? std::string("none") : core::exact_text(run.samples.back().t_s)) + " s) in '" +
              path + "'");
  }
  if (!(std::abs(at->drive.speed_rad_per_s - speed) <= kSameSpeed * speed)) {
    bad_input("--from-run: the run's speed at t = " + core::exact_text(at->t_s) + " s is " +
              core::exact_text(at->drive.speed_rad_per_s) + " rad/s; accepted: --speed " + core::exact_text(speed) +
              " (a run held at the orbit's constant speed)");
  }
  const bool elastic = p.stator_model == core::StatorModel::kElastic;
  RunStart out;
  out.t_s = at->t_s;
  out.angle_rad = std::fmod(at->drive.angle_rad, 2.0 * M_PI);
  if (out.angle_rad < 0.0) out.angle_rad += 2.0 * M_PI;
  out.state.resize(elastic ? 8 : 4);
  const core::Kinematics& k = at->kin;
  if (elastic) {
    out.state << k.rotor_pos, k.stator_pos, k.rotor_vel, k.stator_vel;
  } else {
    out.state << k.rotor_pos, k.rotor_vel;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  namespace cli = rotor_rub::cli;
  std::string scene_path, csv_path, key, run_path;
  bool turning = false;
  std::vector<std::string> sets;
  std::vector<double> range;
  double speed = 0.0, run_at_s = 0.0;
  int periods = 1, settle_periods = 200, doublings = 1;
  CLI::App app(
      "The periodic orbit a Jeffcott scene settles into at a constant speed and its Floquet multipliers (the exact "
      "monodromy of the event-driven flow); with --continue, its branch over a speed range by continuation, its "
      "folds, period doublings and Neimark-Sacker points, and the doubled branches. Rigid contact, prescribed drive.",
      "rotor_rub_orbits");
  cli::add_scene_options(app, scene_path, sets);
  app.add_option("--speed", speed, "the constant speed [rad/s]; required")
      ->type_name("W")
      ->check(cli::number_in(0.0, 1e7, true));
  app.add_option("--periods", periods, "the orbit's period in forcing periods 2 pi / W (period-n)")
      ->type_name("N")
      ->capture_default_str()
      ->check(cli::integer_in(1, 64));
  app.add_option("--settle-periods", settle_periods, "forcing periods run from rest before Newton")
      ->type_name("P")
      ->capture_default_str()
      ->check(cli::integer_in(0, 1000000));
  app.add_option("--from-run", run_path,
                 "start Newton from a run instead (rotor_rub_run --csv of the scene at the constant --speed): its "
                 "sample at --at, the section at its spin angle; an orbit of the run's history (a hysteresis "
                 "band's other branch)")
      ->type_name("CSV")
      ->check(cli::existing_file());
  app.add_flag("--turning", turning,
               "find the orbit periodic in the frame turning with the shaft instead (a scene without gravity and "
               "with its stator centred): its own period T_r, quasi-periodic in the casing; from a start whose "
               "impacts repeat (settled, or --from-run), without --continue, --periods or --csv");
  app.add_option("--at", run_at_s, "with --from-run: the sample's time [s] (the first at or after it)")
      ->type_name("T")
      ->capture_default_str()
      ->check(cli::number_in(0.0, 1e9));
  app.add_option("--continue", range,
                 "trace the orbit's branch both ways within LO..HI [rad/s, or the --parameter key's unit]")
      ->type_name("LO HI")
      ->expected(2)
      ->check(cli::number_in(-1e12, 1e12));
  app.add_option("--parameter", key,
                 "with --continue: trace the branch in this scene key of the model (friction_coefficient, "
                 "restitution, clearance_m, gravity_m_per_s2, ...) at the constant --speed, LO..HI then in its unit; "
                 "default: the speed")
      ->type_name("KEY");
  app.add_option("--doublings", doublings, "with --continue: levels of branches born at period doublings traced")
      ->type_name("K")
      ->capture_default_str()
      ->check(cli::integer_in(0, 8));
  app.add_option(
         "--csv", csv_path,
         "write branch, periods, speed_rad_per_s, parameter, keyphasor, x_m, y_m, radius_m (rotor minus stator at "
         "each keyphasor of each orbit, as rotor_rub_bifurcation's Poincare points), max_multiplier, "
         "stable, events, bifurcation")
      ->type_name("FILE");
  app.footer("Exit status: 0 ok; 2 bad input (usage, scene, a scene it does not model); 3 no periodic orbit found.");
  cli::parse_or_exit(app, argc, argv);
  if (scene_path.empty()) cli::usage_error(app, "--scene is required");
  if (!(speed > 0.0)) cli::usage_error(app, "--speed is required");
  if (!key.empty() && range.empty()) cli::usage_error(app, "--parameter needs --continue LO HI");
  if (run_path.empty() && app.count("--at") > 0) cli::usage_error(app, "--at needs --from-run CSV");
  if (turning && (!range.empty() || periods != 1 || !csv_path.empty())) {
    cli::usage_error(app,
                     "--turning takes no --continue, --periods or --csv (a turning-frame orbit is found, not traced)");
  }
  if (key.empty() && !range.empty() && !(range[0] > 0.0)) {
    cli::usage_error(app, "--continue " + core::exact_text(range[0]) + " ...: a speed range; accepted: 0 < LO");
  }
  core::Scene scene;
  try {
    scene = core::load_scene(scene_path, cli::scene_overrides(sets));
  } catch (const std::exception& e) {
    bad_input(e.what());
  }
  if (core::rotor_kind(scene) != core::RotorKind::kJeffcott) {
    bad_input("scene key 'rotor_file' is '" + scene.rotor.file + "': periodic orbits of the Jeffcott rotor only");
  }
  if (scene.solver.method == core::Method::kPenalty) {
    bad_input("scene key 'method' is 'penalty': the orbits are the rigid contact's; accepted: switching, iteration");
  }
  const core::ModelParameters& p = scene.model;
  // The continuation parameter: the speed, or a key of the model.
  core::ContinuationParameter parameter;
  double start_value = speed;
  std::string unit = "rad/s";
  if (!key.empty()) {
    const auto values = core::scene_values(scene);
    const auto at = values.find(key);
    try {
      if (at == values.end()) {
        core::Scene probe = scene;
        core::set_scene_value(probe, key, "0");  // its refusal names the nearest known key
        bad_input("--parameter: unknown key '" + key + "'");
      }
      start_value = std::stod(at->second);
    } catch (const std::exception& e) {
      bad_input("--parameter: " + std::string(e.what()));
    }
    parameter.name = key;
    parameter.unit = "";  // (the key's name says it)
    unit = key;
    parameter.model = [scene, key](double v) {
      core::Scene s = scene;
      core::set_scene_value(s, key, core::exact_text(v));
      return s.model;
    };
    // A key the model does not hold (a solver's, the drive profile's, the
    // output's) leaves the model as it is: the scene's texts with the model
    // at two values of the key differ only where the model does.
    const double step = std::max(1e-3 * std::abs(start_value), 1e-9);
    bool changes = false;
    for (const double v : {start_value + step, start_value - step}) {
      try {
        core::Scene a = scene, b = scene;
        b.model = parameter.model(v);
        changes = changes || core::scene_values(a) != core::scene_values(b);
      } catch (const std::exception&) {
        // (outside the key's range on this side)
      }
    }
    if (!changes) {
      bad_input("--parameter '" + key +
                "': not a number of the model the orbits are found in (a solver's, the speed profile's or the "
                "output's key); accepted: a model key such as friction_coefficient, restitution, clearance_m, "
                "gravity_m_per_s2, rotor_damping_N_s_per_m");
    }
  }
  if (!range.empty() && !(range[0] < start_value && start_value < range[1])) {
    cli::usage_error(app, "--continue " + core::exact_text(range[0]) + " " + core::exact_text(range[1]) +
                              " does not hold the start's " + (key.empty() ? "--speed" : key) + " " +
                              core::exact_text(start_value) + "; accepted: LO < start < HI");
  }
  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    if (!csv) bad_input("--csv: cannot write '" + csv_path + "'");
    csv.precision(12);
    csv << "branch,periods,speed_rad_per_s,parameter,keyphasor,x_m,y_m,radius_m,max_multiplier,stable,events,"
           "bifurcation\n";
  }
  core::OrbitSettings settings;
  settings.periods = periods;
  core::PeriodicOrbit orbit;
  const auto t0 = std::chrono::steady_clock::now();
  std::string start_text = "the flow run from rest for " + std::to_string(settle_periods) + " periods";
  try {
    Eigen::VectorXd guess;
    if (turning) core::check_turning_scene(p, speed, settings);
    if (run_path.empty()) {
      guess = core::settled_state(p, speed, settle_periods, settings);
    } else {
      const RunStart from = start_from_run(run_path, run_at_s, p, speed);
      guess = from.state;
      settings.section_angle_rad = from.angle_rad;
      start_text = run_path + " at t = " + core::exact_text(from.t_s) + " s (spin angle " +
                   core::exact_text(from.angle_rad) + " rad)";
    }
    if (turning) {
      // The start's time: its spin angle over the speed (the forcing's phase).
      const core::TurningGuess g =
          core::turning_orbit_guess(p, speed, guess, settings.section_angle_rad / speed, kTurningScan, settings);
      orbit = core::find_turning_orbit(p, speed, g, settings);
    } else {
      orbit = core::find_periodic_orbit(p, speed, guess, settings);
    }
  } catch (const std::invalid_argument& e) {
    bad_input(e.what());
  } catch (const core::OrbitError& e) {
    if (turning) {
      std::cerr << "rotor_rub_orbits: no orbit of the turning frame at " << speed << " rad/s: " << e.what()
                << " (settle longer, --settle-periods; or start from a run's later sample, --from-run CSV --at T)\n";
    } else {
      std::cerr << "rotor_rub_orbits: no periodic orbit of " << periods << " period(s) at " << speed
                << " rad/s: " << e.what()
                << " (the motion there may have more periods, --periods N; settle longer, --settle-periods; or "
                   "start from a neighbouring speed's orbit with --continue)\n";
    }
    return 3;
  }
  const double orbit_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s: %s stator, f = %g, e = %g, g = %g m/s^2 (from %s, then Newton: %.3f s of wall time)\n",
              scene_path.c_str(), core::to_string(p.stator_model), p.friction_coefficient, p.restitution,
              p.gravity_m_per_s2, start_text.c_str(), orbit_s);
  orbit.parameter = start_value;
  print_orbit(p, orbit);
  if (range.empty()) {
    if (csv.is_open()) write_rows(csv, 0, orbit, "");
    return 0;
  }
  core::ContinuationSettings cs;
  cs.min_speed_rad_per_s = range[0];
  cs.max_speed_rad_per_s = range[1];
  // Each branch to trace: its start, or a doubling it is born at.
  struct Pending {
    int level;
    core::OrbitBifurcation born_at;
  };
  std::vector<Pending> pending;
  int next_branch = 0;
  std::size_t points = 0;
  const auto t1 = std::chrono::steady_clock::now();
  // The CSV holds each branch in one order along it: the first (traced both
  // ways from the start) from the far end of its trace down, through the
  // start, to the far end of its trace up (reversed: write the down trace
  // backwards; skip: the up trace without its start).
  auto report = [&](int id, const core::OrbitBranch& b, bool reversed, bool skip, int level) {
    if (b.points.empty()) return;
    std::printf("branch %d (period %d): %zu point%s, %.6f to %.6f %s; it ends: %s\n", id, b.points.front().periods,
                b.points.size(), b.points.size() == 1 ? "" : "s", b.points.front().parameter, b.points.back().parameter,
                unit.c_str(), b.end.c_str());
    points += b.points.size();
    for (const core::OrbitBifurcation& bif : b.bifurcations) {
      std::printf("branch %d: %s at %.9f %s\n", id, core::to_string(bif.kind), bif.parameter, unit.c_str());
      if (bif.kind == core::OrbitBifurcationKind::kPeriodDoubling && level < doublings)
        pending.push_back({level + 1, bif});
    }
    if (!csv.is_open()) return;
    auto bifurcations_after = [&](std::size_t j) {
      for (const core::OrbitBifurcation& bif : b.bifurcations) {
        if (bif.after_point == j) write_rows(csv, id, bif.orbit, core::to_string(bif.kind));
      }
    };
    const std::size_t last = b.points.size() - 1;
    for (std::size_t i = 0; i <= last; ++i) {  // each bifurcation between its two points
      const std::size_t j = reversed ? last - i : i;
      if (reversed && j < last) bifurcations_after(j);
      if (j > 0 || !skip) write_rows(csv, id, b.points[j], "");
      if (!reversed) bifurcations_after(j);
    }
  };
  for (const bool up : {false, true}) {
    cs.increasing_speed = up;
    try {
      report(next_branch, core::continue_orbit(p, orbit, cs, settings, parameter, start_value), !up, up, 0);
    } catch (const core::OrbitError& e) {  // the start taken again at a section in free flight failed
      std::printf("branch %d (%s): %s\n", next_branch, up ? "up" : "down", e.what());
    }
  }
  ++next_branch;
  for (std::size_t i = 0; i < pending.size(); ++i) {
    const Pending job = pending[i];
    try {
      // The doubled branch leaves on the single one's unstable side, which
      // the corrector finds; one call traces it.
      report(next_branch++, core::continue_period_doubled(p, job.born_at, cs, settings, parameter), false, false,
             job.level);
    } catch (const core::OrbitError& e) {
      std::printf("the branch born at %.9f %s: %s\n", job.born_at.parameter, unit.c_str(), e.what());
    }
  }
  const double branch_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  std::printf("continuation: %zu orbits on %d branch%s in %.3f s of wall time\n", points, next_branch,
              next_branch == 1 ? "" : "es", branch_s);
  return 0;
}
