// rotor_rub_stability: which synchronous full rubs a Jeffcott scene has over
// a range of speeds, and whether each holds (full_rub_stability.hpp): per
// speed and branch the normal force, the orbits, the least stable
// eigenvalue in the frame turning with the shaft; the folds where branches
// meet, and the speeds where a branch's stability changes, located between
// the grid's speeds (docs/steady_response.md). A flexible rotor (rotor_file)
// is reduced as the scene's runs reduce it; it must be isotropic. The
// contact is the scene method's: rigid (switching, iteration) or the
// penalty's spring and damper (the Jeffcott only). --branch-csv traces the
// branch of the largest normal force by pseudo-arclength continuation
// (full_rub_continuation.hpp) through its folds, its unstable part too.
//
// Exit status: 0 ok; 2 bad input (usage, scene, a scene it does not model).
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "cli_options.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/full_rub_continuation.hpp"
#include "rotor_rub_sim/core/full_rub_stability.hpp"
#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"

namespace {

using namespace rotor_rub;

[[noreturn]] void bad_input(const std::string& msg) {
  std::cerr << "rotor_rub_stability: " << msg << "\n";
  std::exit(2);
}

// The speed in [lo, hi] where pred turns from pred(lo) to !pred(lo), by
// bisection to 1e-9 rad/s or the doubles' resolution there (pred changes
// once in the bracket: the grid's).
template <class Pred>
double located(double lo, double hi, Pred pred) {
  const bool at_lo = pred(lo);
  for (int halvings = 0; halvings < 200 && hi - lo > std::max(1e-9, 4.0 * std::nextafter(hi, 2.0 * hi) - 4.0 * hi);
       ++halvings) {
    const double mid = 0.5 * (lo + hi);
    (pred(mid) == at_lo ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

int main(int argc, char** argv) {
  namespace cli = rotor_rub::cli;
  std::string scene_path, csv_path, branch_path;
  std::vector<std::string> sets;
  std::vector<double> range;
  int speeds = 101;
  CLI::App app(
      "Which synchronous full rubs a scene has between two speeds, and which hold: each branch's normal force, "
      "orbits and least stable eigenvalue (the frame turning with the shaft), the folds and the changes of "
      "stability between them. The Jeffcott or an isotropic flexible rotor (reduced as the scene's runs reduce it) "
      "under "
      "the prescribed drive, rigid contact, no gravity.",
      "rotor_rub_stability");
  cli::add_scene_options(app, scene_path, sets);
  app.add_option("--speeds", range, "the lowest and highest speed [rad/s]; required")
      ->type_name("LO HI")
      ->expected(2)
      ->check(cli::number_in(0.0, 1e7, true));
  app.add_option("--points", speeds, "speeds on the grid, evenly from LO to HI")
      ->type_name("N")
      ->capture_default_str()
      ->check(cli::integer_in(2, 1000000));
  app.add_option("--csv", csv_path,
                 "write speed_rad_per_s, branch, normal_force_N, rotor_orbit_m, stator_orbit_m, growth_rate_per_s, "
                 "frequency_rad_per_s, stable per row (branch 0: the larger normal force)")
      ->type_name("FILE");
  app.add_option("--branch-csv", branch_path,
                 "trace the branch of the largest normal force from the lowest grid speed that has a full rub, by "
                 "pseudo-arclength continuation through its folds (its unstable part too), within LO..HI; write "
                 "speed_rad_per_s, normal_force_N, rotor_orbit_m, stator_orbit_m, growth_rate_per_s, "
                 "frequency_rad_per_s, stable per point in the order traced, and print its folds")
      ->type_name("FILE");
  app.footer("Exit status: 0 ok; 2 bad input (usage, scene, a scene it does not model).");
  cli::parse_or_exit(app, argc, argv);
  if (scene_path.empty()) cli::usage_error(app, "--scene is required");
  if (range.size() != 2 || !(range[0] < range[1])) cli::usage_error(app, "--speeds needs LO < HI");
  core::Scene scene;
  try {
    scene = core::load_scene(scene_path, cli::scene_overrides(sets));
  } catch (const std::exception& e) {
    bad_input(e.what());
  }
  const core::ModelParameters& p = scene.model;
  // The Jeffcott, or a flexible rotor reduced as the scene's runs reduce it.
  std::function<std::vector<core::FullRubStability>(double)> branches;
  std::function<std::size_t(double)> count;
  core::FeRotor rotor;
  core::RotorMatrices full;
  std::shared_ptr<const core::FlexibleRotorModel> reduced;
  try {
    const bool penalty = scene.solver.method == core::Method::kPenalty;
    if (core::rotor_kind(scene) == core::RotorKind::kJeffcott) {
      branches = [&p, penalty](double x) { return core::full_rub_stability(p, x, penalty); };
      count = [&p](double x) { return core::synchronous_full_rub(p, x).size(); };
    } else {
      if (penalty) {
        bad_input(
            "scene key 'method' is 'penalty': a flexible rotor's full rub is linearised with the rigid contact "
            "only; accepted: switching, iteration");
      }
      if (p.gravity_m_per_s2 != 0.0 || p.drive_model != core::DriveModel::kPrescribed) {
        core::full_rub_stability(p, range[0]);  // its refusal names the key
      }
      rotor = core::load_rotor_file(scene.rotor.file);
      full = core::assemble(rotor);
      reduced = core::flexible_rotor_of(scene);
      const core::StationStator stator = core::station_stator(p);
      branches = [&, stator](double x) {
        return core::full_rub_stability(full, rotor.rub_station_node, rotor.unbalances, stator, p.clearance_m,
                                        p.friction_coefficient, x, &reduced->rotor());
      };
      count = [&, stator](double x) {
        return core::synchronous_full_rub(full, rotor.rub_station_node, rotor.unbalances, stator, p.clearance_m,
                                          p.friction_coefficient, x)
            .size();
      };
    }
  } catch (const std::exception& e) {
    bad_input(e.what());  // gravity, a motor, an anisotropic rotor
  }
  std::vector<std::vector<core::FullRubStability>> grid;
  std::vector<double> w(static_cast<std::size_t>(speeds));
  try {
    for (int j = 0; j < speeds; ++j) {
      w[j] = range[0] + (range[1] - range[0]) * j / (speeds - 1);
      grid.push_back(branches(w[j]));
    }
  } catch (const std::exception& e) {
    bad_input(e.what());  // gravity, a motor, an anisotropic rotor, a rest point Newton cannot find
  }
  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    if (!csv) bad_input("--csv: cannot write '" + csv_path + "'");
    csv.precision(10);
    csv << "speed_rad_per_s,branch,normal_force_N,rotor_orbit_m,stator_orbit_m,growth_rate_per_s,"
           "frequency_rad_per_s,stable\n";
  }
  const std::string modes = reduced ? ", " + std::to_string(reduced->rotor().planar_modes) + " planar modes" : "";
  const std::string contact =
      scene.solver.method == core::Method::kPenalty
          ? "the penalty contact (k_c " + core::exact_text(p.contact_stiffness_N_per_m) + " N/m)"
          : std::string("the rigid contact");
  std::printf("%s: synchronous full rub, %s stator, %s, f = %g, %d speeds from %g to %g rad/s%s\n", scene_path.c_str(),
              core::to_string(p.stator_model), contact.c_str(), p.friction_coefficient, speeds, range[0], range[1],
              modes.c_str());
  std::printf("  w [rad/s]  branch  N [N]        |z_r| [m]    growth [1/s]  freq [rad/s]  stable\n");
  for (std::size_t j = 0; j < grid.size(); ++j) {
    for (std::size_t b = 0; b < grid[j].size(); ++b) {
      const core::FullRubStability& s = grid[j][b];
      const std::complex<double> l = s.eigenvalues.front();
      std::printf("  %9.4f  %6zu  %11.5g  %11.5g  %12.5g  %12.5g  %s\n", w[j], b, s.normal_force_N,
                  std::abs(s.station_m), l.real(), std::abs(l.imag()), s.stable() ? "yes" : "no");
      if (csv.is_open()) {
        csv << w[j] << "," << b << "," << s.normal_force_N << "," << std::abs(s.station_m) << ","
            << std::abs(s.stator_m) << "," << l.real() << "," << std::abs(l.imag()) << "," << (s.stable() ? 1 : 0)
            << "\n";
      }
    }
  }
  try {
    // Between grid speeds: a fold where two branches meet (the count changes
    // by two), the free orbit touching the bore where one branch's normal
    // force passes 0 (by one), a change of stability where the upper
    // branch's verdict flips.
    for (std::size_t j = 1; j < grid.size(); ++j) {
      if (grid[j].size() != grid[j - 1].size()) {
        const double at = located(w[j - 1], w[j], [&](double x) { return count(x) == grid[j - 1].size(); });
        const bool fold = grid[j].size() + 2 == grid[j - 1].size() || grid[j - 1].size() + 2 == grid[j].size();
        std::printf("%s at %.6f rad/s: %zu branches below, %zu above\n",
                    fold ? "fold" : "a branch's normal force passes 0 (the free orbit touches the bore)", at,
                    grid[j - 1].size(), grid[j].size());
      } else if (!grid[j].empty() && grid[j].front().stable() != grid[j - 1].front().stable()) {
        auto stable = [&branches](double x) {
          const auto b = branches(x);
          return !b.empty() && b.front().stable();
        };
        const double at = located(w[j - 1], w[j], stable);
        const auto there = branches(at);
        const bool pair = !there.empty() && std::abs(there.front().eigenvalues.front().imag()) > 0.0;
        std::printf("the upper branch turns %s at %.6f rad/s (%s)\n", grid[j].front().stable() ? "stable" : "unstable",
                    at, pair ? "a complex pair crosses: flutter" : "a real eigenvalue crosses");
      }
    }
  } catch (const std::exception& e) {
    bad_input(e.what());  // a rest point Newton cannot find near a fold
  }
  if (!branch_path.empty()) {
    const auto first = std::find_if(grid.begin(), grid.end(), [](const auto& g) { return !g.empty(); });
    if (first == grid.end()) {
      std::printf("continuation: no full rub on the grid to start from\n");
      return 0;
    }
    const double start = w[static_cast<std::size_t>(first - grid.begin())];
    std::ofstream out(branch_path);
    if (!out) bad_input("--branch-csv: cannot write '" + branch_path + "'");
    core::ContinuationSettings settings;
    settings.min_speed_rad_per_s = range[0];
    settings.max_speed_rad_per_s = range[1];
    core::FullRubBranch branch;
    try {
      const core::TurningRotor turning = core::rotor_kind(scene) == core::RotorKind::kJeffcott
                                             ? core::turning_rotor(p)
                                             : core::turning_rotor(reduced->rotor(), full, rotor.unbalances);
      core::PenaltyContact penalty{p.contact_stiffness_N_per_m, core::contact_damping_N_s_per_m(core::StationModel(p))};
      const bool with_penalty = scene.solver.method == core::Method::kPenalty;
      branch = core::continue_full_rub(turning, core::station_stator(p), p.clearance_m, p.friction_coefficient,
                                       first->front(), start, settings, with_penalty ? &penalty : nullptr);
    } catch (const std::exception& e) {
      bad_input(e.what());
    }
    out.precision(12);
    out << "speed_rad_per_s,normal_force_N,rotor_orbit_m,stator_orbit_m,growth_rate_per_s,frequency_rad_per_s,stable\n";
    for (const core::FullRubBranchPoint& pt : branch.points) {
      const std::complex<double> l = pt.rub.eigenvalues.front();
      out << pt.speed_rad_per_s << "," << pt.rub.normal_force_N << "," << std::abs(pt.rub.station_m) << ","
          << std::abs(pt.rub.stator_m) << "," << l.real() << "," << std::abs(l.imag()) << ","
          << (pt.rub.stable() ? 1 : 0) << "\n";
    }
    std::printf("continuation from %g rad/s: %zu points, ended by %s\n", start, branch.points.size(),
                branch.end.c_str());
    for (const double fold : branch.folds_rad_per_s) std::printf("continuation: fold at %.9f rad/s\n", fold);
    for (const double change : branch.stability_changes_rad_per_s) {
      std::printf("continuation: stability changes at %.9f rad/s\n", change);
    }
  }
  return 0;
}
