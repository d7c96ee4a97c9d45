// rotor_rub_modal: modal analysis of a flexible rotor (a rotor file,
// docs/rotors.md): natural frequencies at rest, the Campbell diagram (damped
// frequencies and whirl against speed) as CSV, the critical speeds where the
// synchronous line crosses it (--critical-speeds, on the Campbell diagram's
// speeds), the unbalance response at a node against
// speed (--response) and the mode shapes at rest (--shapes). scripts/plot_campbell.py draws the CSVs. With
// --station, the modal truncation study at a rub station
// (modal_convergence.hpp): reduced models of 1, 2, 4, ... planar modes
// against the full model, and the smallest within --tolerance. With
// --export-matrices, the assembled rotor as a matrices rotor file (its
// nonzeros, exact), for another FE program or a faster read.
//
// Exit status: 0 ok; 2 bad input (usage, a bad rotor file).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "cli_options.hpp"
#include "modal_convergence.hpp"
#include "rotor_rub_sim/core/fe_rotor.hpp"
#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/rotor_reduction.hpp"

namespace {

[[noreturn]] void bad_input(const std::string& msg) {
  std::cerr << "rotor_rub_modal: " << msg << "\n";
  std::exit(2);
}

// The modal truncation study's table and recommendation.
void print_truncation_study(const rotor_rub::core::FeRotor& rotor, const rotor_rub::core::RotorMatrices& m, int station,
                            const std::vector<int>& probes, int count, double max_speed, int speeds,
                            const std::vector<rotor_rub::core::RotorUnbalance>& unbalances, double tolerance) {
  namespace tools = rotor_rub::tools;
  tools::TruncationStudy study;
  study.station_node = station;
  study.probe_nodes = probes;
  study.modes = count;
  study.max_speed_rad_per_s = max_speed;
  study.speeds = speeds;
  study.unbalances = unbalances;
  const std::vector<tools::TruncationRow> rows = tools::truncation_rows(rotor, m, study);
  std::printf("modal truncation at the rub station (node %d), against the full model (%d DOF):\n", station,
              rotor.dofs());
  std::printf("  frequencies: the %d lowest at 0 and %g rad/s, relative",
              std::min(count, static_cast<int>(rotor_rub::core::modes(m, 0.0, count).size())), max_speed);
  if (!unbalances.empty()) {
    std::printf("; response: unbalance");
    for (const auto& u : unbalances) std::printf(" %g kg m at node %d (%g rad)", u.me_kg_m, u.node, u.phase_rad);
    std::printf(", %d speeds to %g rad/s, at the station", speeds - 1, max_speed);
    if (!probes.empty()) std::printf(" and probe nodes");
    for (const int p : probes) std::printf(" %d", p);
    std::printf(", relative to the rotor's largest displacement");
  }
  std::printf("\n  planar modes  coordinates  station mass [kg]  frequency error  response error\n");
  for (const auto& row : rows) {
    std::printf("  %12d  %11d  %17.4f  %15.2e  %14.2e\n", row.planar_modes, 2 * row.planar_modes, row.station_mass_kg,
                row.frequency_error, row.response_error);
  }
  const tools::TruncationRow* best = tools::smallest_within(rows, tolerance);
  if (best != nullptr) {
    std::printf("smallest model within %g: %d planar modes (%d coordinates)\n", tolerance, best->planar_modes,
                2 * best->planar_modes);
  }
}

// The assembled rotor as a rotor file of matrices (docs/rotors.md): the
// nodes' positions, M, K, C, G by their nonzeros in 17 digits (the same
// doubles back), and the file's stations. Returns false when not written.
bool write_matrices_file(const std::string& path, const std::string& source, const rotor_rub::core::FeRotor& rotor,
                         const rotor_rub::core::RotorMatrices& m) {
  std::ofstream out(path);
  if (!out) return false;
  char num[32];
  auto number = [&num](double v) {
    std::snprintf(num, sizeof num, "%.17g", v);
    return std::string(num);
  };
  out << "# rotor_rub_modal --export-matrices of " << source << ": the assembled matrices, nonzeros only.\n";
  out << "matrices:\n  nodes_z_m: [";
  for (int node = 0; node < rotor.nodes(); ++node) out << (node ? ", " : "") << number(rotor.node_z_m(node));
  out << "]\n";
  if (m.support_nodes > 0) out << "  support_nodes: " << m.support_nodes << "\n";
  for (const auto& [key, mat] :
       {std::pair<const char*, const Eigen::MatrixXd*>{"M", &m.M}, {"K", &m.K}, {"C", &m.C}, {"G", &m.G}}) {
    out << "  " << key << ":\n    size: " << mat->rows() << "\n    nonzeros:";
    bool any = false;
    for (Eigen::Index i = 0; i < mat->rows(); ++i) {
      for (Eigen::Index j = 0; j < mat->cols(); ++j) {
        if ((*mat)(i, j) == 0.0) continue;
        out << "\n      - [" << i << ", " << j << ", " << number((*mat)(i, j)) << "]";
        any = true;
      }
    }
    out << (any ? "\n" : " []\n");
  }
  if (rotor.rub_station_node >= 0) {
    out << "rub_station: {node: " << rotor.rub_station_node;
    if (rotor.rub_contact_radius_m > 0.0) out << ", contact_radius_m: " << number(rotor.rub_contact_radius_m);
    out << "}\n";
  }
  if (!rotor.unbalances.empty()) out << "unbalances:\n";
  for (const auto& u : rotor.unbalances) {
    out << "  - {node: " << u.node << ", me_kg_m: " << number(u.me_kg_m) << ", phase_rad: " << number(u.phase_rad)
        << "}\n";
  }
  if (!rotor.probe_nodes.empty()) out << "probes:\n";
  for (const int p : rotor.probe_nodes) out << "  - {node: " << p << "}\n";
  return static_cast<bool>(out);
}

}  // namespace

int main(int argc, char** argv) {
  namespace cli = rotor_rub::cli;
  namespace core = rotor_rub::core;
  std::string rotor_path, campbell_csv, response_csv, shapes_csv, export_path;
  double max_speed = 1000.0, me = 0.0;
  int speeds = 101, count = 6, unbalance_node = -1, probe_node = -1, station = -1;
  std::vector<int> probe_nodes;
  std::vector<core::RotorUnbalance> unbalances;
  bool study = false, criticals = false;
  double tolerance = 1e-3;
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
  CLI::App app(
      "Modal analysis of a flexible rotor: natural frequencies at rest, the Campbell diagram, critical speeds and "
      "the unbalance response (docs/rotors.md).",
      "rotor_rub_modal");
  app.add_option("--rotor", rotor_path, "the rotor file (YAML; config/rotors/); required")
      ->type_name("FILE")
      ->required()
      ->check(cli::existing_file());
  app.add_option("--max-speed", max_speed, "the Campbell diagram's top speed [rad/s]")
      ->type_name("RAD_PER_S")
      ->capture_default_str()
      ->check(cli::number_in(0.0, 1e6, true));
  app.add_option("--speeds", speeds, "speeds from 0 to --max-speed, evenly spaced")
      ->type_name("N")
      ->capture_default_str()
      ->check(cli::integer_in(2, 100000));
  app.add_option("--modes", count, "modes per speed (the lowest)")
      ->type_name("N")
      ->capture_default_str()
      ->check(cli::integer_in(1, 1000));
  app.add_flag("--critical-speeds", criticals,
               "print the critical speeds up to --max-speed (a mode's damped frequency equal to the speed), bracketed "
               "on the --speeds grid and located to 1e-12 (an eigensolve per speed: on a rotor of hundreds of DOF, "
               "seconds)");
  app.add_option("--campbell", campbell_csv, "write speed, mode, w_d, w_n, zeta, whirl per row to this CSV")
      ->type_name("FILE");
  app.add_option("--jobs", jobs,
                 "speeds solved in parallel for --campbell and --critical-speeds (default: all cores, " +
                     std::to_string(jobs) + "; the same values at any number)")
      ->type_name("N")
      ->check(cli::integer_in(1, 1024));
  app.add_option("--unbalance-node", unbalance_node,
                 "node of an unbalance (with --unbalance-kg-m), in place of the rotor file's unbalances")
      ->type_name("NODE")
      ->check(cli::integer_in(0, 100000));
  app.add_option("--unbalance-kg-m", me, "the unbalance m e [kg m]")
      ->type_name("KG_M")
      ->check(cli::number_in(0, 1e6, true));
  app.add_option("--response-node", probe_node, "node whose response to write (default: the first unbalance's)")
      ->type_name("NODE")
      ->check(cli::integer_in(0, 100000));
  app.add_option("--response", response_csv, "write speed, |x|, phase x, |y|, phase y, forward, backward per row")
      ->type_name("FILE");
  app.add_option("--shapes", shapes_csv,
                 "write the mode shapes at rest: mode, node, z, x and y (real and imaginary parts) per row; each "
                 "mode scaled so that its largest displacement is 1")
      ->type_name("FILE");
  app.add_flag("--study", study,
               "print the modal truncation study at the rub station (the rotor file's, or --station): reduced models "
               "of 1, 2, 4, ... planar modes against the full model; with unbalances, the unbalance response over "
               "the speeds at the station and the probes too");
  app.add_option("--station", station,
                 "the rub station's node for the study (default: the rotor file's); implies --study")
      ->type_name("NODE")
      ->check(cli::integer_in(0, 100000));
  app.add_option("--probe-nodes", probe_nodes,
                 "nodes of the probes the study compares (default: the rotor file's probes, else the bearings' nodes)")
      ->type_name("NODE ...")
      ->check(cli::integer_in(0, 100000));
  app.add_option("--tolerance", tolerance,
                 "the study's recommendation: the smallest model whose frequency and response errors are within it")
      ->type_name("REL")
      ->capture_default_str()
      ->check(cli::number_in(0.0, 1.0, true));
  app.add_option("--export-matrices", export_path,
                 "write the assembled rotor as a rotor file of matrices (M, K, C, G by their nonzeros, exact; the "
                 "stations kept): for another FE program, or a faster read")
      ->type_name("FILE");
  app.footer("Exit status: 0 ok; 2 bad input (usage, a bad rotor file).");
  cli::parse_or_exit(app, argc, argv);
  if ((unbalance_node >= 0) != (me > 0.0)) {
    cli::usage_error(app, "--unbalance-node and --unbalance-kg-m go together");
  }
  core::FeRotor rotor;
  core::RotorMatrices m;
  double read_s = 0.0;  // the rotor file's reading, wall time
  try {
    const auto read_start = std::chrono::steady_clock::now();
    rotor = core::load_rotor_file(rotor_path);
    read_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - read_start).count();
    m = core::assemble(rotor);
    for (const auto& [what, node] : {std::pair<const char*, int>{"--unbalance-node", unbalance_node},
                                     {"--response-node", probe_node},
                                     {"--station", station}}) {
      if (node >= rotor.nodes()) {
        throw std::invalid_argument(std::string(what) + ": node " + std::to_string(node) +
                                    " is out of range; accepted: 0 to " + std::to_string(rotor.nodes() - 1));
      }
    }
    for (const int node : probe_nodes) {
      if (node >= rotor.nodes()) {
        throw std::invalid_argument("--probe-nodes: probe node " + std::to_string(node) +
                                    " is out of range; accepted: 0 to " + std::to_string(rotor.nodes() - 1));
      }
    }
    if (station >= 0) study = true;
    if (station < 0 && study) station = rotor.rub_station_node;
    if (study && station < 0) {
      throw std::invalid_argument("--study needs a rub station: the rotor file's rub_station, or --station");
    }
    if (probe_nodes.empty()) probe_nodes = rotor.probe_nodes;
    if (probe_nodes.empty()) {
      for (const auto& b : rotor.bearings) {  // the shaft's bearing nodes (not a pedestal's)
        if (b.node != station && b.node < rotor.nodes() &&
            std::find(probe_nodes.begin(), probe_nodes.end(), b.node) == probe_nodes.end())
          probe_nodes.push_back(b.node);
      }
    }
    if (me > 0.0) unbalances = {{unbalance_node, me, 0.0}};
    if (unbalances.empty()) unbalances = rotor.unbalances;
    if (!response_csv.empty() && unbalances.empty()) {
      throw std::invalid_argument(
          "--response needs an unbalance: the rotor file's, or --unbalance-node and "
          "--unbalance-kg-m");
    }
    if (station >= 0) core::reduce_rotor(rotor, m, station, 1);  // a station the rotor cannot stand on, before output
    if (rotor.imported) {
      const std::string supports =
          rotor.support_nodes() > 0 ? " and " + std::to_string(rotor.support_nodes()) + " support nodes" : "";
      std::printf("%s: %d nodes%s, imported matrices, %d DOF (read in %.3f s)\n", rotor_path.c_str(), rotor.nodes(),
                  supports.c_str(), rotor.dofs(), read_s);
    } else {
      std::printf(
          "%s: %d nodes, %zu shaft elements, %zu disks, %zu bearings, %zu point masses, %d DOF (read in "
          "%.3f s)\n",
          rotor_path.c_str(), rotor.nodes(), rotor.shaft.size(), rotor.disks.size(), rotor.bearings.size(),
          rotor.point_masses.size(), rotor.dofs(), read_s);
    }
    if (!export_path.empty()) {
      if (!write_matrices_file(export_path, rotor_path, rotor, m)) {
        throw std::invalid_argument("--export-matrices: cannot write '" + export_path + "'");
      }
      std::printf("wrote %s\n", export_path.c_str());
    }
    std::printf("at rest:\n  mode  w_d [rad/s]      w_n [rad/s]      zeta        whirl\n");
    int k = 0;
    for (const auto& md : core::modes(m, 0.0, count)) {
      std::printf("  %4d  %15.8f  %15.8f  %10.3e  %s\n", k++, md.damped_frequency_rad_per_s,
                  md.natural_frequency_rad_per_s, md.damping_ratio, core::to_string(md.whirl));
    }
    const core::NonModeRoots left_out = core::non_mode_roots(m, 0.0);
    if (left_out.overdamped > 0) std::printf("  (and %d overdamped roots: no modes, left out)\n", left_out.overdamped);
    if (left_out.diverging > 0) {
      std::printf("  (and %d roots that grow without turning: the rotor diverges, unstable at rest)\n",
                  left_out.diverging);
    }
    if (left_out.rigid_body > 0) {
      std::printf(
          "  (and %d roots below 1 rpm: rigid-body motion, a part of the rotor or its supports with no "
          "stiffness path to the ground)\n",
          left_out.rigid_body);
    }
    if (criticals) {
      std::printf("critical speeds up to %g rad/s (w_d(Omega) = Omega):\n", max_speed);
      for (const auto& c : core::critical_speeds(m, count, max_speed, speeds - 1, jobs)) {
        std::printf("  mode %d: %.6f rad/s (%.3f Hz, %.1f rpm), %s whirl\n", c.mode_index, c.speed_rad_per_s,
                    c.speed_rad_per_s / (2 * M_PI), c.speed_rad_per_s * 30 / M_PI, core::to_string(c.whirl));
      }
    }
    if (station >= 0)
      print_truncation_study(rotor, m, station, probe_nodes, count, max_speed, speeds, unbalances, tolerance);
  } catch (const std::exception& e) {
    bad_input(e.what());
  }
  try {
    if (!campbell_csv.empty()) {
      std::ofstream os(campbell_csv);
      os << "speed_rad_per_s,mode,damped_frequency_rad_per_s,natural_frequency_rad_per_s,damping_ratio,whirl\n";
      os.precision(12);
      // Solved and written a block of speeds at a time: the modes' shapes of
      // every speed at once could outgrow the memory (100000 speeds).
      constexpr int kBlock = 64;
      for (int first = 0; first < speeds; first += kBlock) {
        std::vector<double> block;
        for (int s = first; s < std::min(speeds, first + kBlock); ++s) block.push_back(max_speed * s / (speeds - 1));
        const std::vector<std::vector<core::Mode>> diagram = core::campbell(m, block, count, jobs);
        for (std::size_t s = 0; s < block.size(); ++s) {
          int k = 0;
          for (const auto& md : diagram[s]) {
            os << block[s] << "," << k++ << "," << md.damped_frequency_rad_per_s << ","
               << md.natural_frequency_rad_per_s << "," << md.damping_ratio << "," << core::to_string(md.whirl) << "\n";
          }
        }
      }
      if (!os) bad_input("cannot write '" + campbell_csv + "'");
    }
    if (!shapes_csv.empty()) {
      std::ofstream os(shapes_csv);
      os << "mode,node,z_m,x_re,x_im,y_re,y_im,damped_frequency_rad_per_s,whirl\n";
      os.precision(12);
      int k = 0;
      for (const auto& md : core::modes(m, 0.0, count)) {
        // Scaled so that the largest displacement is 1 (the shape's largest
        // entry may be a tilt); a mode without displacement stays as it is.
        double largest = 0.0;
        for (int node = 0; node < rotor.nodes(); ++node) {
          largest = std::max({largest, std::abs(md.shape(core::dof_index(node, core::kDofX))),
                              std::abs(md.shape(core::dof_index(node, core::kDofY)))});
        }
        const double scale = largest > 1e-6 ? 1.0 / largest : 1.0;
        for (int node = 0; node < rotor.nodes(); ++node) {
          const double z = rotor.node_z_m(node);
          const std::complex<double> x = scale * md.shape(core::dof_index(node, core::kDofX)),
                                     y = scale * md.shape(core::dof_index(node, core::kDofY));
          os << k << "," << node << "," << z << "," << x.real() << "," << x.imag() << "," << y.real() << "," << y.imag()
             << "," << md.damped_frequency_rad_per_s << "," << core::to_string(md.whirl) << "\n";
        }
        ++k;
      }
      if (!os) bad_input("cannot write '" + shapes_csv + "'");
    }
    if (!response_csv.empty()) {
      const int at = probe_node >= 0 ? probe_node : unbalances.front().node;
      std::ofstream os(response_csv);
      os << "speed_rad_per_s,x_m,x_phase_rad,y_m,y_phase_rad,forward_m,backward_m\n";
      os.precision(12);
      for (int s = 1; s < speeds; ++s) {
        const double w = max_speed * s / (speeds - 1);
        const Eigen::VectorXcd q = core::unbalance_response(m, unbalances, w);
        const std::complex<double> x = q(core::dof_index(at, core::kDofX)), y = q(core::dof_index(at, core::kDofY));
        // x + i y = F e^{iwt} + B e^{-iwt}: forward F = (X + i Y) / 2, backward B = conj(X - i Y) / 2.
        const std::complex<double> i(0.0, 1.0);
        os << w << "," << std::abs(x) << "," << std::arg(x) << "," << std::abs(y) << "," << std::arg(y) << ","
           << std::abs(x + i * y) / 2 << "," << std::abs(x - i * y) / 2 << "\n";
      }
      if (!os) bad_input("cannot write '" + response_csv + "'");
    }
  } catch (const std::exception& e) {  // a solver that does not converge at some speed
    bad_input(e.what());
  }
  return 0;
}
