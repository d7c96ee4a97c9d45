// The finite-element rotor (fe_rotor.hpp, rotor_file.hpp) against closed forms
// and a published reference: ROSS's example rotor to the digits ROSS documents;
// a uniform pinned shaft converging to Timoshenko's frequency equation (and
// not to Euler-Bernoulli's, which leaves out shear and rotary inertia); a
// one-disk rotor on a light shaft giving the Jeffcott's frequency, shear
// included; the gyroscopic split of forward and backward whirl; bad files.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <complex>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

#include "rotor/for_each_index.hpp"
#include "rotor_file_support.hpp"
#include "rotor_rub_sim/core/fe_rotor.hpp"
#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/rotor_reduction.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

core::FeRotor ross_example() { return core::load_rotor_file(test::source_path("config/rotors/ross_example.yaml")); }

std::vector<double> damped(const core::RotorMatrices& m, double speed, int count) {
  std::vector<double> w;
  for (const auto& md : core::modes(m, speed, count)) w.push_back(md.damped_frequency_rad_per_s);
  return w;
}

// A uniform steel shaft, length L in n elements, pinned at both ends (x and y
// held by bearings of 1e14 N/m; the rotations free).
core::FeRotor pinned_shaft(double length_m, double diameter_m, int n) {
  core::FeRotor r;
  core::ShaftElement e;
  e.length_m = length_m / n;
  e.outer_diameter_m = diameter_m;
  r.shaft.assign(static_cast<std::size_t>(n), e);
  for (const int node : {0, n}) r.bearings.push_back({node, 1e14, 0, 0, 1e14, 0, 0, 0, 0});
  return r;
}

using test::load_error;
using test::write_file;

}  // namespace

// ROSS documents M(0)[:4, :4] of its example and its frequencies at rest:
// rotor_example().run_modal(0).wn[:2] = [91.79655318, 96.28899977] (printed
// to 8 decimals: 5e-9 rad/s), and rounded to whole rad/s [92, 96, 275, 297].
TEST(FeRotor, RossExampleToTheDigitsRossPublishes) {
  const core::RotorMatrices m = core::assemble(ross_example());
  ASSERT_EQ(m.M.rows(), 28);
  const double documented[4][4] = {{1.42050794, 0, 0, 0.04931719},
                                   {0, 1.42050794, -0.04931719, 0},
                                   {0, -0.04931719, 0.00231392, 0},
                                   {0.04931719, 0, 0, 0.00231392}};
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) EXPECT_NEAR(m.M(i, j), documented[i][j], 5e-9) << i << "," << j;
  }
  EXPECT_NEAR(m.G(0, 1), 0.01943344, 5e-9);  // ROSS's G[:4, :4] doctest
  const std::vector<double> w = damped(m, 0.0, 4);
  ASSERT_EQ(w.size(), 4u);
  EXPECT_NEAR(w[0], 91.79655318, 5e-9);
  EXPECT_NEAR(w[1], 96.28899977, 5e-9);
  const double rounded[4] = {92, 96, 275, 297};
  for (int k = 0; k < 4; ++k) EXPECT_EQ(std::round(w[k]), rounded[k]) << k;
  // Undamped bearings: w_n = w_d, zeta = 0.
  for (const auto& md : core::modes(m, 0.0, 4)) {
    EXPECT_NEAR(md.natural_frequency_rad_per_s, md.damped_frequency_rad_per_s, 1e-9);
    EXPECT_NEAR(md.damping_ratio, 0.0, 1e-12);
  }
}

// ROSS's run_critical_speed on its example: [92, 96, 271, 300] rad/s rounded.
// The first two barely move with speed (the disks sit where the first
// modes hardly tilt them); the next two split by gyroscopics.
TEST(FeRotor, RossExampleCriticalSpeeds) {
  const auto cs = core::critical_speeds(core::assemble(ross_example()), 4, 400.0, 40);
  ASSERT_EQ(cs.size(), 4u);
  const double rounded[4] = {92, 96, 271, 300};
  for (int k = 0; k < 4; ++k) EXPECT_EQ(std::round(cs[static_cast<std::size_t>(k)].speed_rad_per_s), rounded[k]) << k;
}

// Gyroscopics: at speed the third and fourth modes split into a backward
// whirl that falls and a forward whirl that rises (the Campbell diagram).
TEST(FeRotor, ForwardWhirlRisesAndBackwardFallsWithSpeed) {
  const core::RotorMatrices m = core::assemble(ross_example());
  const auto at_rest = core::modes(m, 0.0, 4);
  const auto running = core::modes(m, 500.0, 4);
  EXPECT_EQ(running[2].whirl, core::ModeWhirl::kBackward);
  EXPECT_EQ(running[3].whirl, core::ModeWhirl::kForward);
  EXPECT_LT(running[2].damped_frequency_rad_per_s, at_rest[2].damped_frequency_rad_per_s);
  EXPECT_GT(running[3].damped_frequency_rad_per_s, at_rest[3].damped_frequency_rad_per_s);
}

// A uniform pinned shaft's n-th bending frequency (wavenumber k = n pi / L)
// solves Timoshenko's frequency equation
//   (rho^2 I / (kappa G)) w^4 - (rho A + k^2 (rho I + E I rho / (kappa G))) w^2 + E I k^4 = 0
// (its lower root); Euler-Bernoulli's k^2 sqrt(E I / (rho A)) leaves out
// shear and rotary inertia. The FE frequency converges to Timoshenko's as
// the elements shrink, at second order (measured: the error falls 4.2 to
// 4.5 times per halving, 6.9e-6 at 32 elements for n = 1).
TEST(FeRotor, UniformShaftConvergesToTimoshenkosFrequencyEquation) {
  const double L = 1.0, d = 0.1;  // stocky: shear and rotary inertia show (d / L = 0.1)
  const core::Material steel;
  const double A = M_PI * d * d / 4, I = M_PI * std::pow(d, 4) / 64, rho = steel.density_kg_per_m3,
               E = steel.youngs_modulus_Pa, G = steel.shear_modulus_Pa;
  const double kappa = core::cowper_shear_coefficient(steel.poisson_ratio(), 0.0);
  for (int n : {1, 2}) {
    const double k = n * M_PI / L;
    const double a = rho * rho * I / (kappa * G), b = rho * A + k * k * (rho * I + E * I * rho / (kappa * G)),
                 c = E * I * std::pow(k, 4);
    const double timoshenko = std::sqrt((b - std::sqrt(b * b - 4 * a * c)) / (2 * a));
    const double euler_bernoulli = k * k * std::sqrt(E * I / (rho * A));
    double previous_error = 1.0;
    for (int elements : {4, 8, 16, 32}) {
      // Each bending frequency comes twice (x and y planes): mode 2n - 1.
      const double w = damped(core::assemble(pinned_shaft(L, d, elements)), 0.0, 2 * n)[2 * n - 1];
      const double error = std::abs(w - timoshenko) / timoshenko;
      // Second order: at least 3.5 times smaller per halving (4 would be exact).
      EXPECT_LT(error, previous_error / 3.5) << "n " << n << ", " << elements << " elements";
      previous_error = error;
    }
    // 32 elements: within 2e-4 of Timoshenko's (measured 6.9e-6 for n = 1,
    // 1.05e-4 for n = 2), while Euler-Bernoulli's differs by 1.2 % and 4.7 %
    // at d / L = 0.1: the FE follows Timoshenko's theory, not Euler's.
    EXPECT_LT(previous_error, 2e-4) << n;
    EXPECT_GT(std::abs(euler_bernoulli - timoshenko) / timoshenko, 1e-2) << n;
  }
}

// The paper's Jeffcott as a one-disk FE rotor (config/rotors/paper_jeffcott.yaml):
// a point mass m at midspan of a light shaft on stiff bearings k_b, whose
// midspan stiffness is k = 1 / (L^3 / (48 E I) + L / (4 kappa G A) + 1 / (2 k_b))
// (bending, shear, the two bearings in parallel; two elements are exact for
// a point load: its static deflection is a cubic per element). The shaft's
// own mass m_s adds 17/35 of itself (Rayleigh, the static deflection's
// shape): w = sqrt(k / (m + 17 m_s / 35)). Rayleigh's error is second order
// in m_s / m = 1.8e-4, and the shape's shear part (2e-4 of the deflection)
// moves the 17/35 by less than that: 1e-7 bounds both. Against the paper's
// sqrt(2493 / 0.418): the shaft's mass and the bearings' compliance (5e-5
// together) and the diameter's 5 digits: within 1e-4.
TEST(FeRotor, OneDiskRotorIsTheJeffcott) {
  const core::FeRotor r = core::load_rotor_file(test::source_path("config/rotors/paper_jeffcott.yaml"));
  const core::ShaftElement& e = r.shaft[0];
  const double L = 2 * e.length_m, d = e.outer_diameter_m, A = M_PI * d * d / 4, I = M_PI * std::pow(d, 4) / 64;
  const double kappa = core::cowper_shear_coefficient(e.material.poisson_ratio(), 0.0);
  const double kb = r.bearings[0].kxx;
  const double k = 1.0 / (L * L * L / (48 * e.material.youngs_modulus_Pa * I) +
                          L / (4 * kappa * e.material.shear_modulus_Pa * A) + 1.0 / (2 * kb));
  const double m = r.disks[0].mass_kg, ms = e.material.density_kg_per_m3 * A * L;
  const double w = damped(core::assemble(r), 0.0, 1)[0];
  EXPECT_NEAR(w / std::sqrt(k / (m + 17.0 * ms / 35.0)), 1.0, 1e-7);
  const core::Scene paper = test::paper_scene();
  EXPECT_NEAR(w / std::sqrt(paper.model.rotor_stiffness_N_per_m / paper.model.rotor_mass_kg), 1.0, 1e-4);
}

namespace {

// A rotor file of matrices (docs/rotors.md), each entry at max_digits10.
std::string matrices_file(const core::RotorMatrices& m, const std::vector<double>& z, const std::string& extra = "") {
  std::ostringstream os;
  os.precision(17);
  os << "matrices:\n  nodes_z_m: [";
  for (std::size_t i = 0; i < z.size(); ++i) os << (i ? ", " : "") << z[i];
  os << "]\n";
  for (const auto& [key, x] :
       {std::pair<const char*, const Eigen::MatrixXd*>{"M", &m.M}, {"K", &m.K}, {"C", &m.C}, {"G", &m.G}}) {
    os << "  " << key << ":\n";
    for (int i = 0; i < x->rows(); ++i) {
      os << "    - [";
      for (int j = 0; j < x->cols(); ++j) os << (j ? ", " : "") << (*x)(i, j);
      os << "]\n";
    }
  }
  return os.str() + extra;
}

}  // namespace

// Matrices exported by another FE program: ROSS's example written as
// matrices (17 digits: the doubles round-trip exactly) is the same rotor,
// its modes identical to the bit; stations work on it as on elements.
TEST(FeRotor, ImportedMatricesAreTheSameRotor) {
  const core::FeRotor elements = ross_example();
  const core::RotorMatrices m = core::assemble(elements);
  std::vector<double> z;
  for (int node = 0; node < elements.nodes(); ++node) z.push_back(elements.node_z_m(node));
  const core::FeRotor imported = core::load_rotor_file(
      write_file("matrices.yaml", matrices_file(m, z, "rub_station: {node: 3, contact_radius_m: 0.025}\n")));
  ASSERT_TRUE(imported.imported.has_value());
  EXPECT_EQ(imported.nodes(), 7);
  EXPECT_DOUBLE_EQ(imported.node_z_m(6), 1.5);
  EXPECT_EQ(imported.rub_station_node, 3);
  for (double speed : {0.0, 500.0}) EXPECT_EQ(damped(core::assemble(imported), speed, 4), damped(m, speed, 4)) << speed;
  // What the physics demands of the matrices.
  auto error_with = [&](auto change) {
    core::RotorMatrices bad = m;
    change(bad);
    return load_error(matrices_file(bad, z));
  };
  EXPECT_NE(error_with([](core::RotorMatrices& b) { b.M(0, 1) += 1.0; }).find("key 'M': not symmetric"),
            std::string::npos);
  EXPECT_NE(error_with([](core::RotorMatrices& b) { b.M(5, 5) = -1.0; }).find("key 'M': not positive definite"),
            std::string::npos);
  EXPECT_NE(error_with([](core::RotorMatrices& b) { b.G(2, 3) = 1.0; }).find("key 'G': not skew-symmetric"),
            std::string::npos);
  EXPECT_NE(load_error("matrices:\n  nodes_z_m: [0]\n  M: [[1, 0, 0, 0], [0, 1, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n"
                       "  K: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n")
                .find("key 'M': row 1 has 3 entries; accepted: 4"),
            std::string::npos);
  EXPECT_NE(load_error("matrices:\n  nodes_z_m: [0]\n  M: [[1, 0, 0, 0]]\n  K: [[1]]\n").find("key 'M': 1 rows"),
            std::string::npos);
  EXPECT_NE(load_error("shaft:\n  - {length_m: 0.5, outer_diameter_m: 0.05}\n" + matrices_file(m, z))
                .find("gives both 'matrices' and 'shaft'"),
            std::string::npos);
}

// Cross-coupled bearings (kxy 2.5e6, kyx -2e5 beside kxx 1e6, kyy 6e5 N/m,
// cxy 300, cyx -100 N s/m) give K and C whose symmetric parts are
// indefinite: circulatory forces, which a file must be able to carry. As
// matrices the rotor is its element file's: the same modes to the bit, and
// the same reduced model at the rub station.
TEST(FeRotor, CrossCoupledBearingsImportAsTheirElementFile) {
  core::FeRotor elements = ross_example();
  for (core::BearingElement& b : elements.bearings) {
    b.kxx = 1e6, b.kyy = 6e5, b.kxy = 2.5e6, b.kyx = -2e5;
    b.cxy = 300.0, b.cyx = -100.0;
  }
  const core::RotorMatrices m = core::assemble(elements);
  const Eigen::MatrixXd k_sym = 0.5 * (m.K + m.K.transpose()), c_sym = 0.5 * (m.C + m.C.transpose());
  ASSERT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(k_sym).eigenvalues().minCoeff(), 0.0);
  ASSERT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(c_sym).eigenvalues().minCoeff(), 0.0);
  std::vector<double> z;
  for (int node = 0; node < elements.nodes(); ++node) z.push_back(elements.node_z_m(node));
  const core::FeRotor imported = core::load_rotor_file(write_file("cross_coupled.yaml", matrices_file(m, z)));
  const core::RotorMatrices back = core::assemble(imported);
  EXPECT_EQ(back.K, m.K);
  EXPECT_EQ(back.C, m.C);
  for (double speed : {0.0, 500.0}) EXPECT_EQ(damped(back, speed, 6), damped(m, speed, 6)) << speed;
  const core::ReducedRotor from_elements = core::reduce_rotor(elements, m, 3, 4);
  const core::ReducedRotor from_matrices = core::reduce_rotor(imported, back, 3, 4);
  EXPECT_EQ(from_matrices.matrices.K, from_elements.matrices.K);
  EXPECT_EQ(from_matrices.matrices.C, from_elements.matrices.C);
}

// ROSS's save_mat writes the node positions as "nodes" and 6 DOF per node,
// [x, y, z, alpha, beta, theta]: read as the lateral rotor, the axial and
// torsional DOFs (here with their own mass and stiffness) dropped; a
// matrix that couples them to the lateral ones is refused, naming the entry.
TEST(FeRotor, RossSixDofMatricesAreTheLateralRotor) {
  const core::FeRotor elements = ross_example();
  const core::RotorMatrices m = core::assemble(elements);
  const int nodes = elements.nodes();
  auto six_of = [&](const Eigen::MatrixXd& four, double axial, double torsional) {
    Eigen::MatrixXd six = Eigen::MatrixXd::Zero(6 * nodes, 6 * nodes);
    constexpr int kLateral[4] = {0, 1, 3, 4};
    for (int a = 0; a < 4 * nodes; ++a) {
      for (int b = 0; b < 4 * nodes; ++b)
        six(6 * (a / 4) + kLateral[a % 4], 6 * (b / 4) + kLateral[b % 4]) = four(a, b);
    }
    for (int node = 0; node < nodes; ++node) {
      six(6 * node + 2, 6 * node + 2) = axial;
      six(6 * node + 5, 6 * node + 5) = torsional;
    }
    return six;
  };
  core::RotorMatrices six;
  six.M = six_of(m.M, 3.0, 0.01);
  six.K = six_of(m.K, 1e8, 1e5);
  six.C = six_of(m.C, 0.0, 0.0);
  six.G = six_of(m.G, 0.0, 0.0);
  std::vector<double> z;
  for (int node = 0; node < nodes; ++node) z.push_back(elements.node_z_m(node));
  std::string text = matrices_file(six, z);
  text.replace(text.find("nodes_z_m"), 9, "nodes");
  const core::FeRotor imported = core::load_rotor_file(write_file("ross_six.yaml", text));
  const core::RotorMatrices back = core::assemble(imported);
  EXPECT_EQ(back.M, m.M);
  EXPECT_EQ(back.K, m.K);
  EXPECT_EQ(back.G, m.G);
  six.K(6 * 2 + 0, 6 * 2 + 2) = six.K(6 * 2 + 2, 6 * 2 + 0) = 1e4;  // node 2's x coupled to its z
  std::string coupled = matrices_file(six, z);
  EXPECT_NE(load_error(coupled).find("key 'K': row 12 column 14 couples a lateral DOF to an axial or torsional one"),
            std::string::npos)
      << load_error(coupled);
  EXPECT_NE(load_error(text + "  nodes_z_m: [0]\n").find("gives both 'nodes_z_m' and 'nodes'"), std::string::npos);
}

// The matrices by their nonzeros ({size, nonzeros: [[row, col, value]]}),
// as rotor_rub_modal --export-matrices writes them: the same rotor as the
// rows (ROSS's example, cross-coupled bearings: every matrix exact), in 4 and
// in ROSS's 6 DOF per node; a bad entry refused naming it.
TEST(FeRotor, SparseMatricesAreTheRows) {
  core::FeRotor elements = ross_example();
  for (core::BearingElement& b : elements.bearings) b.kxy = 2.5e6, b.kyx = -2e5, b.cxy = 300.0;
  const core::RotorMatrices m = core::assemble(elements);
  std::vector<double> z;
  for (int node = 0; node < elements.nodes(); ++node) z.push_back(elements.node_z_m(node));
  auto sparse_file = [&z](const core::RotorMatrices& x, const std::string& nodes_key) {
    std::ostringstream os;
    os.precision(17);
    os << "matrices:\n  " << nodes_key << ": [";
    for (std::size_t i = 0; i < z.size(); ++i) os << (i ? ", " : "") << z[i];
    os << "]\n";
    for (const auto& [key, mat] :
         {std::pair<const char*, const Eigen::MatrixXd*>{"M", &x.M}, {"K", &x.K}, {"C", &x.C}, {"G", &x.G}}) {
      os << "  " << key << ": {size: " << mat->rows() << ", nonzeros: [";
      bool first = true;
      for (int i = 0; i < mat->rows(); ++i) {
        for (int j = 0; j < mat->cols(); ++j) {
          if ((*mat)(i, j) == 0.0) continue;
          os << (first ? "" : ", ") << "[" << i << ", " << j << ", " << (*mat)(i, j) << "]";
          first = false;
        }
      }
      os << "]}\n";
    }
    return os.str();
  };
  const std::string text = sparse_file(m, "nodes_z_m");
  const core::RotorMatrices back = core::assemble(core::load_rotor_file(write_file("sparse.yaml", text)));
  EXPECT_EQ(back.M, m.M);
  EXPECT_EQ(back.K, m.K);
  EXPECT_EQ(back.C, m.C);
  EXPECT_EQ(back.G, m.G);
  // ROSS's 6 DOF per node: told by M's size.
  const int nodes = elements.nodes();
  auto six_of = [&](const Eigen::MatrixXd& four) {
    Eigen::MatrixXd six = Eigen::MatrixXd::Zero(6 * nodes, 6 * nodes);
    constexpr int kLateral[4] = {0, 1, 3, 4};
    for (int a = 0; a < 4 * nodes; ++a) {
      for (int b = 0; b < 4 * nodes; ++b)
        six(6 * (a / 4) + kLateral[a % 4], 6 * (b / 4) + kLateral[b % 4]) = four(a, b);
    }
    return six;
  };
  core::RotorMatrices six{six_of(m.M), six_of(m.K), six_of(m.C), six_of(m.G)};
  for (int node = 0; node < nodes; ++node) six.M(6 * node + 2, 6 * node + 2) = six.M(6 * node + 5, 6 * node + 5) = 1.0;
  const core::RotorMatrices lateral =
      core::assemble(core::load_rotor_file(write_file("sparse_six.yaml", sparse_file(six, "nodes"))));
  EXPECT_EQ(lateral.M, m.M);
  EXPECT_EQ(lateral.K, m.K);
  // Bad entries.
  const std::string k_line = text.substr(text.find("  K: "), text.find("  C: ") - text.find("  K: "));
  auto with_k = [&](const std::string& k) { return std::string(text).replace(text.find(k_line), k_line.size(), k); };
  EXPECT_NE(load_error(with_k("  K: {size: 28, nonzeros: [[0, 0, 1.0], [0, 0, 2.0]]}\n"))
                .find("matrices key 'K' key 'nonzeros': entry 1 gives row 0 column 0 again"),
            std::string::npos);
  EXPECT_NE(load_error(with_k("  K: {size: 28, nonzeros: [[28, 0, 1.0]]}\n"))
                .find("entry 0: row 28 is out of range; accepted: 0 to 27"),
            std::string::npos);
  EXPECT_NE(load_error(with_k("  K: {size: 28, nonzeros: [[0, 2.5, 1.0]]}\n")).find("column 2.5 is out of range"),
            std::string::npos);
  EXPECT_NE(load_error(with_k("  K: {size: 12, nonzeros: []}\n"))
                .find("key 'size': value 12 is out of range; accepted: 28 (the nodes' DOFs)"),
            std::string::npos);
  EXPECT_NE(
      load_error(with_k("  K: {size: 28, nonzero: []}\n")).find("unknown key 'nonzero'; did you mean 'nonzeros'?"),
      std::string::npos)
      << load_error(with_k("  K: {size: 28, nonzero: []}\n"));
  EXPECT_NE(load_error(with_k("  K: {size: 28, nonzeros: [[0, 0, .nan]]}\n")).find("value .nan is not finite"),
            std::string::npos);
}

// Modal damping (the rotor file's modal_damping: {ratio}, ROSS's
// modal_damping_ratio): C = M Phi diag(2 zeta w) Phi^T M makes each undamped
// mode a damped oscillator of exactly that ratio where nothing else damps it
// and at rest (a pinned shaft: bearings without dampers), to the eigensolver's
// rounding (1e-9: the pinned supports' 1e14 N/m set the largest eigenvalue);
// read from a file as from the struct; beside shaft damping, refused.
TEST(FeRotor, ModalDampingGivesEveryModeItsRatio) {
  core::FeRotor r = pinned_shaft(1.0, 0.05, 10);
  r.modal_damping_ratios = {0.02};
  const auto md = core::modes(core::assemble(r), 0.0, 6);
  ASSERT_EQ(md.size(), 6u);
  for (const auto& mode : md) EXPECT_NEAR(mode.damping_ratio, 0.02, 1e-9) << mode.natural_frequency_rad_per_s;
  const core::FeRotor from_file = core::load_rotor_file(
      write_file("modal_damping.yaml",
                 "modal_damping: {ratio: 0.02}\n"
                 "shaft:\n  - {elements: 10, length_m: 0.1, outer_diameter_m: 0.05}\n"
                 "bearings:\n  - {node: 0, kxx: 1e14, kyy: 1e14}\n  - {node: 10, kxx: 1e14, kyy: 1e14}\n"));
  EXPECT_EQ(from_file.modal_damping_ratios, std::vector<double>{0.02});
  EXPECT_EQ(core::assemble(from_file).C, core::assemble(r).C);
  EXPECT_NE(load_error("modal_damping: {ratio: 0.02}\nshaft_damping: {stiffness_proportional_s: 1e-5}\n"
                       "shaft:\n  - {length_m: 0.5, outer_diameter_m: 0.05}\n")
                .find("gives both 'shaft_damping' and 'modal_damping'"),
            std::string::npos);
  EXPECT_NE(load_error("modal_damping: {ratio: 1.5}\nshaft:\n  - {length_m: 0.5, outer_diameter_m: 0.05}\n")
                .find("modal_damping key 'ratio': value 1.5 is out of range; accepted: [0, 1]"),
            std::string::npos)
      << load_error("modal_damping: {ratio: 1.5}\nshaft:\n  - {length_m: 0.5, outer_diameter_m: 0.05}\n");
}

namespace {

// A 1 m shaft of 50 mm in 10 elements on two bearings kx, ky: on soft ones
// its lowest modes move it rigidly (the strain energy in the bearings), on
// stiff ones every mode bends it.
core::FeRotor shaft_on_bearings(double kx, double ky) {
  core::FeRotor r = pinned_shaft(1.0, 0.05, 10);
  for (core::BearingElement& b : r.bearings) {
    b.kxx = kx;
    b.kyy = ky;
  }
  return r;
}

// Every mode alone gets its ratio to rounding (the C built from the very
// modes it damps: ModalDampingGivesEveryModeItsRatio's bound).
constexpr double kModalRatioTolerance = 1e-9;

}  // namespace

// The i-th natural frequency gets the i-th ratio, the last one every higher
// one: on an isotropic rotor each frequency is double (its two planes) and
// counts once; on anisotropic bearings the planes part and count apart.
TEST(FeRotor, ModalDampingRatiosGoByNaturalFrequency) {
  const std::vector<double> ratios{0.03, 0.02, 0.01};
  core::FeRotor iso = shaft_on_bearings(1e14, 1e14);
  iso.modal_damping_ratios = ratios;
  const auto twin = core::modes(core::assemble(iso), 0.0, 8);
  ASSERT_EQ(twin.size(), 8u);
  for (std::size_t i = 0; i < twin.size(); ++i) {
    EXPECT_NEAR(twin[i].damping_ratio, ratios[std::min<std::size_t>(i / 2, 2)], kModalRatioTolerance) << i;
  }
  core::FeRotor aniso = shaft_on_bearings(1e6, 4e6);
  aniso.modal_damping_ratios = ratios;
  const auto parted = core::modes(core::assemble(aniso), 0.0, 6);
  ASSERT_EQ(parted.size(), 6u);
  ASSERT_GT(parted[1].natural_frequency_rad_per_s, 1.2 * parted[0].natural_frequency_rad_per_s);  // planes apart
  for (std::size_t i = 0; i < parted.size(); ++i) {
    EXPECT_NEAR(parted[i].damping_ratio, ratios[std::min<std::size_t>(i, 2)], kModalRatioTolerance) << i;
  }
  // higher_ratio for the modes past the list (ROSS's default_damping_ratio).
  aniso.modal_damping_higher_ratio = 0.0;
  const auto cut = core::modes(core::assemble(aniso), 0.0, 6);
  ASSERT_EQ(cut.size(), 6u);
  for (std::size_t i = 0; i < cut.size(); ++i) {
    EXPECT_NEAR(cut[i].damping_ratio, i < 3 ? ratios[i] : 0.0, kModalRatioTolerance) << i;
  }
  aniso.modal_damping_higher_ratio.reset();
  const core::FeRotor from_file = core::load_rotor_file(
      write_file("modal_ratios.yaml",
                 "modal_damping: {ratios: [0.03, 0.02, 0.01]}\n"
                 "shaft:\n  - {elements: 10, length_m: 0.1, outer_diameter_m: 0.05}\n"
                 "bearings:\n  - {node: 0, kxx: 1e6, kyy: 4e6}\n  - {node: 10, kxx: 1e6, kyy: 4e6}\n"));
  EXPECT_EQ(core::assemble(from_file).C, core::assemble(aniso).C);
  const std::string shaft = "shaft:\n  - {length_m: 0.5, outer_diameter_m: 0.05}\n";
  EXPECT_NE(load_error("modal_damping: {ratios: [0.03, 1.2]}\n" + shaft)
                .find("modal_damping key 'ratios': entry 1 '1.2' is out of range; accepted: a number in [0, 1]"),
            std::string::npos);
  EXPECT_NE(load_error("modal_damping: {ratios: []}\n" + shaft).find("key 'ratios' is empty or not a list"),
            std::string::npos);
  EXPECT_NE(load_error("modal_damping: {ratios: [{a: 1}]}\n" + shaft)
                .find("key 'ratios': entry 0 is not a number; accepted: a number in [0, 1]"),
            std::string::npos);
  EXPECT_NE(load_error("modal_damping: {ratio: 0.01, higher_ratio: 0}\n" + shaft)
                .find("gives 'higher_ratio' without 'ratios'"),
            std::string::npos);
  const core::FeRotor higher = core::load_rotor_file(
      write_file("higher_ratio.yaml", "modal_damping: {ratios: [0.03], higher_ratio: 0.001}\n" + shaft));
  EXPECT_EQ(higher.modal_damping_higher_ratio, std::optional<double>(0.001));
  EXPECT_NE(load_error("modal_damping: {ratio: 0.01, loss_factor: 1e-3}\n" + shaft)
                .find("gives 2 of 'ratio', 'ratios', 'loss_factor'; accepted: one"),
            std::string::npos);
}

// A material loss factor eta damps each mode by the shaft's share of its
// strain energy (the modal strain energy method): zeta = (eta / 2) (1 -
// E_b / E), E_b = sum kx |x_b|^2 + ky |y_b|^2 over the bearings and E =
// w^2 q^H M q, both from the mode's own shape. On stiff bearings (1e9 N/m, a
// rolling bearing's) every mode bends the shaft (zeta -> eta / 2); on soft
// ones the lowest barely does.
TEST(FeRotor, ALossFactorDampsTheShaftsShareOfEachMode) {
  constexpr double eta = 2e-3;
  // The undamped solver's vectors, which err by eps times the stiffest
  // mode's w^2 over the gap (on bearings of 1e14 N/m, a pinning by penalty,
  // that reaches 6e-5 of zeta; here below 1e-9).
  constexpr double kShareTolerance = 1e-9 * eta / 2.0;
  double lowest_share = 1.0, highest_share = 0.0;
  for (const double k : {1e6, 1e9}) {
    core::FeRotor r = shaft_on_bearings(k, 4.0 * k);
    r.shaft_loss_factor = eta;
    const core::RotorMatrices m = core::assemble(r);
    const auto md = core::modes(m, 0.0, 8);
    ASSERT_EQ(md.size(), 8u);
    for (const core::Mode& mode : md) {
      const Eigen::VectorXcd& q = mode.shape;
      double bearing_energy = 0.0;
      for (const core::BearingElement& b : r.bearings) {
        bearing_energy += b.kxx * std::norm(q(core::dof_index(b.node, core::kDofX))) +
                          b.kyy * std::norm(q(core::dof_index(b.node, core::kDofY)));
      }
      const double w = mode.natural_frequency_rad_per_s;
      const double share = 1.0 - bearing_energy / (w * w * q.dot(m.M * q).real());
      EXPECT_NEAR(mode.damping_ratio, eta / 2.0 * share, kShareTolerance) << "k " << k << ", w " << w;
      lowest_share = std::min(lowest_share, share);
      highest_share = std::max(highest_share, share);
    }
  }
  EXPECT_LT(lowest_share, 0.2);    // a rigid mode on soft bearings
  EXPECT_GT(highest_share, 0.99);  // bending between stiff ones
  EXPECT_NE(load_error("modal_damping: {loss_factor: 3}\nshaft:\n  - {length_m: 0.5, outer_diameter_m: 0.05}\n")
                .find("modal_damping key 'loss_factor': value 3 is out of range; accepted: [0, 2]"),
            std::string::npos);
  EXPECT_NE(load_error("modal_damping: {loss_factor: 1e-3}\nmatrices:\n  nodes: [0]\n"
                       "  M: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n"
                       "  K: [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]\n")
                .find("modal_damping's 'loss_factor', which needs the shaft's elements"),
            std::string::npos);
}

// Bearings cross-coupled enough that K's symmetric part is indefinite (kxx
// 1e6, kyy 6e5, kxy 2.5e6, kyx -2e5: CrossCoupledBearingsImportAsTheirElementFile)
// have no modes of (M, K_sym) that are the rotor's: modal damping is refused,
// named, where it would leave the negative one undamped.
TEST(FeRotor, ModalDampingRefusesAnIndefiniteStiffness) {
  const std::string rotor =
      "shaft:\n  - {elements: 6, length_m: 0.1, outer_diameter_m: 0.05}\n"
      "bearings:\n  - {node: 0, kxx: 1e6, kyy: 6e5, kxy: 2.5e6, kyx: -2e5}\n"
      "  - {node: 6, kxx: 1e6, kyy: 6e5, kxy: 2.5e6, kyx: -2e5}\n";
  EXPECT_EQ(load_error(rotor), "accepted");
  for (const char* damping : {"modal_damping: {ratio: 0.01}\n", "modal_damping: {loss_factor: 1e-3}\n"}) {
    EXPECT_NE(load_error(damping + rotor).find("modal_damping: K's symmetric part has the eigenvalue -"),
              std::string::npos)
        << load_error(damping + rotor);
  }
}

// ROSS's damped rig (config/rotors/ross_rub_rig.yaml: proportional damping
// with beta 1e-5 s overdamps every mode above 2e5 rad/s) has a pair at
// critical damping near 1.05e5 rad/s, which the QR returns with an
// imaginary part of 1.5e-8 of itself (sqrt(eps): a double root): no mode.
// The modes are its shaft's, from 181.8 rad/s (ROSS's first bending pair).
TEST(FeRotor, NearlyCriticalPairsAreNoModes) {
  const core::RotorMatrices m =
      core::assemble(core::load_rotor_file(test::source_path("config/rotors/ross_rub_rig.yaml")));
  const auto md = core::modes(m, 0.0, 4);
  ASSERT_EQ(md.size(), 4u);
  EXPECT_NEAR(md.front().damped_frequency_rad_per_s, 181.77, 0.01);
  for (const auto& mode : md) EXPECT_LT(mode.damping_ratio, 0.05) << mode.damped_frequency_rad_per_s;
  EXPECT_GT(core::non_mode_roots(m, 0.0).overdamped, 100);
}

namespace {

// A rigid disk on a bearing, as the matrices of one node (x, y, alpha,
// beta): mass m and translational springs kx, ky; tilt inertia I_d, polar
// I_p (the gyroscopic coupling, as fe_rotor.cpp's disk), tilt spring k_t and
// damper c_t.
core::RotorMatrices disk_on_bearing(double m, double kx, double ky, double id, double ip, double kt, double ct) {
  core::RotorMatrices mat;
  mat.M = Eigen::Vector4d(m, m, id, id).asDiagonal();
  mat.K = Eigen::Vector4d(kx, ky, kt, kt).asDiagonal();
  mat.C = Eigen::Vector4d(0.0, 0.0, ct, ct).asDiagonal();
  mat.G = Eigen::Matrix4d::Zero();
  mat.G(core::kDofAlpha, core::kDofBeta) = ip;
  mat.G(core::kDofBeta, core::kDofAlpha) = -ip;
  return mat;
}

}  // namespace

// An overdamped pair that the spin turns complex is no mode. A disk's tilt
// with damping c_t, in z = alpha + i beta: I_d l^2 + (c_t - i Omega I_p) l
// + k_t = 0; the real system's roots are these two and their conjugates,
// one of each pair with Im > 0. For c_t^2 >> 4 I_d k_t both have
// Im l / |Re l| = Omega I_p / c_t: at 0.01 they decay by exp(2 pi / 0.01)
// in a cycle. Only the translation, sqrt(k / m) forward and backward, is a
// mode. On ROSS's damped rig at 1000 rad/s such pairs sit at 23 rad/s,
// below every shaft mode: the lowest
// modes listed are the shaft's (as at rest, lightly damped), and the first
// critical speed is found (181.4 rad/s, its mode at 181.8 at rest; with the
// pairs taken for modes, none was).
TEST(FeRotor, OverdampedPairsTurnedByTheSpinAreNoModes) {
  const double m = 10.0, k = 1e6, id = 0.1, kt = 2e4, ip = 0.2, ct = 1000.0, speed = 0.01 * ct / ip;
  const core::RotorMatrices mat = disk_on_bearing(m, k, k, id, ip, kt, ct);
  const std::complex<double> b(ct, -speed * ip);
  const std::complex<double> root = std::sqrt(b * b - 4.0 * id * kt);
  for (const std::complex<double> tilt : {(-b + root) / (2.0 * id), (-b - root) / (2.0 * id)}) {
    EXPECT_NEAR(std::abs(tilt.imag() / tilt.real()), 0.01, 1e-3) << tilt;  // the closed form's premise
  }
  const auto md = core::modes(mat, speed, 4);
  ASSERT_EQ(md.size(), 2u);
  for (const auto& mode : md) EXPECT_NEAR(mode.damped_frequency_rad_per_s, std::sqrt(k / m), 1e-9);
  EXPECT_EQ(core::non_mode_roots(mat, speed).overdamped, 2);

  const core::RotorMatrices rig =
      core::assemble(core::load_rotor_file(test::source_path("config/rotors/ross_rub_rig.yaml")));
  const auto at_speed = core::modes(rig, 1000.0, 4);
  ASSERT_EQ(at_speed.size(), 4u);
  EXPECT_GT(at_speed.front().damped_frequency_rad_per_s, 150.0);
  for (const auto& mode : at_speed) EXPECT_LT(mode.damping_ratio, 0.05) << mode.damped_frequency_rad_per_s;
  const auto critical = core::critical_speeds(rig, 1, 200.0, 4);
  ASSERT_EQ(critical.size(), 1u);
  EXPECT_NEAR(critical[0].speed_rad_per_s, 185.0, 10.0);
}

// A negative stiffness in x (a disk on a bearing that pushes it off centre):
// the x translation's roots are +-sqrt(k / m) = +-100 1/s, real. The growing
// one is neither a mode nor overdamped but a divergence; the decaying one is
// overdamped; the y translation (100 rad/s) and the tilts are modes.
TEST(FeRotor, ANegativeStiffnessDivergesAndIsNoMode) {
  const core::RotorMatrices mat = disk_on_bearing(1.0, -1e4, 1e4, 0.1, 0.2, 1e5, 0.0);
  EXPECT_EQ(core::non_mode_roots(mat, 0.0).diverging, 1);
  EXPECT_EQ(core::non_mode_roots(mat, 0.0).overdamped, 1);
  const std::vector<core::Mode> listed = core::modes(mat, 0.0, 10);
  ASSERT_EQ(listed.size(), 3u);  // y, and the tilt's two
  EXPECT_NEAR(listed[0].damped_frequency_rad_per_s, 100.0, 1e-9 * 100.0);
  EXPECT_EQ(core::non_mode_roots(disk_on_bearing(1.0, 1e4, 1e4, 0.1, 0.2, 1e5, 0.0), 0.0).diverging, 0);
}

// A disk whose tilt is overdamped at rest (c_t^2 > 4 I_d k_t): the spin turns
// its pair into modes at about 93.5 rad/s (Im / -Re above 0.174, the modes'
// bound), the slow one near 15 rad/s, below the translations, whose critical
// speeds are sqrt(k / m) exactly (no coupling): 100 and 101 rad/s, both in
// the sampled interval (92.25, 102.5] where the tilt enters. A search by mode
// index lost the second: the translation that crossed at 101 was the highest
// mode at 92.25, and the entry moved it to an index empty there.
TEST(FeRotor, AModeEnteringBelowHidesNoCriticalSpeed) {
  const double m = 1.0, kx = 1e4, ky = 101.0 * 101.0, id = 0.005, ip = 0.01, kt = 500.0, ct = 6.2;
  const core::RotorMatrices mat = disk_on_bearing(m, kx, ky, id, ip, kt, ct);
  const double max_speed = 205.0;
  const int samples = 20;  // speeds 10.25 rad/s apart: 92.25, 102.5, ...
  // The premise: two modes at 92.25 rad/s; at 102.5 the tilt's two, one below.
  ASSERT_EQ(core::modes(mat, 92.25, 8).size(), 2u);
  const auto above = core::modes(mat, 102.5, 8);
  ASSERT_EQ(above.size(), 4u);
  EXPECT_LT(above[0].damped_frequency_rad_per_s, 20.0);

  const auto critical = core::critical_speeds(mat, 4, max_speed, samples);
  ASSERT_EQ(critical.size(), 2u);
  EXPECT_NEAR(critical[0].speed_rad_per_s, std::sqrt(kx / m), 1e-9);
  EXPECT_EQ(critical[0].mode_index, 1);  // the slow tilt below it
  EXPECT_NEAR(critical[1].speed_rad_per_s, std::sqrt(ky / m), 1e-9);
  EXPECT_EQ(critical[1].mode_index, 2);
  // Asked for the lowest mode only: at 100 and 101 rad/s the lowest is the
  // tilt, which never meets the synchronous line.
  EXPECT_TRUE(core::critical_speeds(mat, 1, max_speed, samples).empty());
}

// Three disks, uncoupled (block-diagonal matrices): the one above, whose
// tilt enters the modes near 93.5 rad/s, and two without damping, I_p = 2
// I_d, translations at 1e5 rad/s (with the other's, a root of multiplicity
// 4), tilts whirling at -+Omega + sqrt(Omega^2 + k_t / I_d).
namespace {
constexpr double kThreeDisksId = 0.005;
constexpr std::array<double, 2> kThreeDisksKtPerId = {35323.0, 36000.0};
core::RotorMatrices three_disks() {
  const std::array<core::RotorMatrices, 3> disks = {
      disk_on_bearing(1.0, 1e4, 101.0 * 101.0, kThreeDisksId, 0.01, 500.0, 6.2),
      disk_on_bearing(1.0, 1e10, 1e10, kThreeDisksId, 2.0 * kThreeDisksId, kThreeDisksKtPerId[0] * kThreeDisksId, 0.0),
      disk_on_bearing(1.0, 1e10, 1e10, kThreeDisksId, 2.0 * kThreeDisksId, kThreeDisksKtPerId[1] * kThreeDisksId, 0.0)};
  core::RotorMatrices all;
  for (Eigen::MatrixXd core::RotorMatrices::*part :
       {&core::RotorMatrices::M, &core::RotorMatrices::K, &core::RotorMatrices::C, &core::RotorMatrices::G}) {
    all.*part = Eigen::MatrixXd::Zero(12, 12);
    for (int d = 0; d < 3; ++d) (all.*part).block(4 * d, 4 * d, 4, 4) = disks[static_cast<std::size_t>(d)].*part;
  }
  return all;
}
}  // namespace

// Each mode's root and shape solve the quadratic problem, and the fourfold
// root keeps four independent shapes. Its third copy was refined onto no
// root at all, a mode at 301.9 rad/s growing at a damping ratio of -0.025,
// its iterates' left and right vectors paired badly (refined_qep_root).
TEST(FeRotor, AFourfoldRootKeepsItsFourModes) {
  const core::RotorMatrices all = three_disks();
  const double speed = 92.25;
  // A mode's backward error |Q x| / (|l|^2 |M x| + |l| |D x| + |K x|): at
  // most 1e-9 measured on the tests' rotors; 0.24 for the failed copy.
  constexpr double kBackwardError = 1e-8;
  // An undamped mode's ratio is its refined root's rounding (about 1e-16).
  constexpr double kUndampedRatioRounding = 1e-12;
  const std::vector<core::Mode> modes = core::modes(all, speed, 12);
  ASSERT_EQ(modes.size(), 10u);  // the first disk's tilt is not yet a mode
  Eigen::MatrixXcd fourfold(12, 4);
  for (std::size_t i = 0; i < modes.size(); ++i) {
    const std::complex<double> l(-modes[i].damping_ratio * modes[i].natural_frequency_rad_per_s,
                                 modes[i].damped_frequency_rad_per_s);
    const Eigen::VectorXcd& x = modes[i].shape;
    const Eigen::VectorXcd mx = all.M * x, dx = (all.C + speed * all.G) * x, kx = all.K * x;
    EXPECT_LE((l * l * mx + l * dx + kx).norm(),
              kBackwardError * (std::norm(l) * mx.norm() + std::abs(l) * dx.norm() + kx.norm()))
        << i;
    EXPECT_GE(modes[i].damping_ratio, -kUndampedRatioRounding) << i;  // every disk is passive
    if (i >= 6) {
      EXPECT_NEAR(modes[i].damped_frequency_rad_per_s, 1e5, 1e-9 * 1e5) << i;
      fourfold.col(static_cast<Eigen::Index>(i) - 6) = x.normalized();
    }
  }
  // Independent: the four unit shapes' smallest singular value far from 0.
  EXPECT_GT(Eigen::JacobiSVD<Eigen::MatrixXcd>(fourfold).singularValues().minCoeff(), 0.1);
}

// The critical-speed search looks for the modes up to 1.5 max_speed + 1
// (308.5 rad/s here). In (92.25, 102.5] the first disk's two tilt modes enter
// that list (the slow one at 16 rad/s, the other at 221) while the two other
// disks' forward tilts leave it: the list is as long at both ends, each index
// another mode. The backward tilts cross the synchronous line at sqrt(k_t /
// (3 I_d)). The crossings are found all the same here: below the list's top
// the k-th lowest damped frequency only jumps down where a mode enters below
// it, and every crossing here is downward (a mode above the line falling
// through it), so each is a continuous sign change of one index; the jump's
// own sign change is no mode's, refused by the refined modes there.
TEST(FeRotor, ModesLeavingTheSearchAsOthersEnterHideNoCriticalSpeed) {
  const core::RotorMatrices all = three_disks();
  const double max_speed = 205.0, searched_to = 1.5 * max_speed + 1.0;
  const int samples = 20;
  // The premise: as many modes below 308.5 rad/s at either end, not the same.
  auto searched = [&](double speed) {
    std::vector<double> w;
    for (const core::Mode& md : core::modes(all, speed, 12)) {
      if (md.damped_frequency_rad_per_s <= searched_to) w.push_back(md.damped_frequency_rad_per_s);
    }
    return w;
  };
  const std::vector<double> before = searched(92.25), after = searched(102.5);
  ASSERT_EQ(before.size(), 6u);
  ASSERT_EQ(after.size(), 6u);
  EXPECT_GT(before.back(), 300.0);  // the forward tilts, leaving
  EXPECT_LT(after.front(), 20.0);   // the slow tilt, entered

  const auto critical = core::critical_speeds(all, 12, max_speed, samples);
  ASSERT_EQ(critical.size(), 4u);
  EXPECT_NEAR(critical[0].speed_rad_per_s, 100.0, 1e-9);
  EXPECT_NEAR(critical[1].speed_rad_per_s, 101.0, 1e-9);
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(critical[2 + i].speed_rad_per_s, std::sqrt(kThreeDisksKtPerId[i] / 3.0), 1e-9);
    EXPECT_EQ(critical[2 + i].whirl, core::ModeWhirl::kBackward);
  }
}

// A rigid disk on a bearing, as matrices: its tilt, I_d theta'' -+ Omega I_p
// theta' + k_t theta = 0, whirls at w = (-+Omega I_p + sqrt((Omega I_p)^2 + 4
// I_d k_t)) / (2 I_d), backward the lower; its translation at sqrt(k / m).
// The tilt modes move no displacement: their whirl is the slopes'.
TEST(FeRotor, PureTiltWhirlsAsItsSlopes) {
  const double m = 10.0, k = 1e6, id = 0.1, kt = 2e4, ip = 0.2, speed = 500.0;
  const core::RotorMatrices mat = disk_on_bearing(m, k, k, id, ip, kt, 0.0);
  const auto md = core::modes(mat, speed, 4);
  ASSERT_EQ(md.size(), 4u);
  const double root = std::sqrt(std::pow(speed * ip, 2) + 4 * id * kt);
  EXPECT_NEAR(md[0].damped_frequency_rad_per_s, (root - speed * ip) / (2 * id), 1e-9);
  EXPECT_EQ(md[0].whirl, core::ModeWhirl::kBackward);
  EXPECT_NEAR(md[1].damped_frequency_rad_per_s, std::sqrt(k / m), 1e-9);
  EXPECT_NEAR(md[3].damped_frequency_rad_per_s, (root + speed * ip) / (2 * id), 1e-9);
  EXPECT_EQ(md[3].whirl, core::ModeWhirl::kForward);
  // The translation is a double root (no coupling moves it): two shapes of
  // its own, translations without tilt, independent (orthogonal: the
  // refinement projects the first out of the second).
  // No tilt: inverse iteration at the translation's root shrinks the tilt
  // rows by (distance to the translation / distance to a tilt root)^k per
  // solve, far below 1e-12 after four (measured: below 1e-40).
  constexpr double kTiltLeftAtMost = 1e-12;
  // Orthogonal to the projection's rounding: two Gram-Schmidt passes leave
  // a few eps of the first vector (1e-9: far above them, far below a shape
  // that kept the first's direction, whose product is 1).
  constexpr double kOverlapAtMost = 1e-9;
  EXPECT_NEAR(md[2].damped_frequency_rad_per_s, std::sqrt(k / m), 1e-9);
  for (const int i : {1, 2}) {
    const Eigen::VectorXcd& q = md[static_cast<std::size_t>(i)].shape;
    ASSERT_TRUE(q.allFinite()) << i;
    EXPECT_LT(q.tail(2).norm(), kTiltLeftAtMost * q.head(2).norm()) << i;
  }
  EXPECT_LT(std::abs(md[1].shape.dot(md[2].shape)), kOverlapAtMost * md[1].shape.norm() * md[2].shape.norm());
}

// The stations a rotor file names: unbalances, the rub station, the probes.
TEST(FeRotor, StationsOfTheSealRubExample) {
  const core::FeRotor r = core::load_rotor_file(test::source_path("config/rotors/seal_rub.yaml"));
  ASSERT_EQ(r.unbalances.size(), 2u);
  EXPECT_EQ(r.unbalances[1].node, 9);
  EXPECT_DOUBLE_EQ(r.unbalances[1].me_kg_m, 4.4e-5);
  EXPECT_DOUBLE_EQ(r.unbalances[1].phase_rad, 1.5708);
  EXPECT_EQ(r.rub_station_node, 6);
  EXPECT_DOUBLE_EQ(r.rub_contact_radius_m, 0.05);
  EXPECT_EQ(r.probe_nodes, (std::vector<int>{0, 12}));
  const core::FeRotor ross = ross_example();
  EXPECT_EQ(ross.rub_station_node, -1);  // none named
  EXPECT_TRUE(ross.unbalances.empty());
}

TEST(FeRotor, BadFilesNameTheItemTheKeyAndTheRange) {
  const std::string shaft = "shaft:\n  - {elements: 2, length_m: 0.5, outer_diameter_m: 0.05}\n";
  EXPECT_NE(load_error(shaft + "disks:\n  - {node: 3, mass_kg: 1}\n")
                .find("disk 0 key 'node': value 3 is out of range; accepted: [0, 2]"),
            std::string::npos)
      << load_error(shaft + "disks:\n  - {node: 3, mass_kg: 1}\n");
  EXPECT_NE(load_error("shaft:\n  - {length_m: -0.5, outer_diameter_m: 0.05}\n").find("shaft entry 0 key 'length_m'"),
            std::string::npos);
  EXPECT_NE(load_error(shaft + "bearings:\n  - {node: 0, kxy: 1e5, kyyy: 1e6}\n").find("did you mean 'kyy'?"),
            std::string::npos);
  EXPECT_NE(load_error(shaft + "bearings:\n  - {node: 1.5, kxx: 1e6}\n").find("is not a node number"),
            std::string::npos);
  EXPECT_NE(load_error("shaft:\n  - {length_m: 0.5, outer_diameter_m: 0.05, inner_diameter_m: 0.05}\n")
                .find("accepted: [0, outer_diameter_m)"),
            std::string::npos);
  EXPECT_NE(load_error("material: {shear_modulus_Pa: 50e9}\n" + shaft).find("Poisson's ratio"), std::string::npos);
  EXPECT_NE(load_error("disks: []\n").find("lacks the list 'shaft'"), std::string::npos);
  EXPECT_NE(load_error(shaft + "unbalances:\n  - {node: 3, me_kg_m: 1e-4}\n")
                .find("unbalance 0 key 'node': value 3 is out of range; accepted: [0, 2]"),
            std::string::npos);
  EXPECT_NE(load_error(shaft + "unbalances:\n  - {node: 1, me_kg_m: -1e-4}\n").find("unbalance 0 key 'me_kg_m'"),
            std::string::npos);
  EXPECT_NE(load_error(shaft + "rub_station: {node: 1}\n").find("rub_station lacks the key 'contact_radius_m'"),
            std::string::npos);
  EXPECT_NE(load_error(shaft + "probes:\n  - {nod: 1}\n").find("did you mean 'node'?"), std::string::npos);
  EXPECT_NE(load_error("shaft: [\n").find("cannot be read"), std::string::npos);
}

// Rayleigh damping of the shaft (shaft_damping, or a shaft entry's own
// damping): on a free-free uniform shaft C = alpha M + beta K throughout, so
// every elastic mode keeps its undamped frequency w and takes the ratio
// alpha / (2 w) + beta w / 2 (lambda^2 + (alpha + beta w^2) lambda + w^2 = 0;
// |lambda| = w). 1e-9: the eigenvalues' rounding over a spread of 1e5 in
// frequency. The rigid-body roots (0 and -alpha) and the overdamped high
// modes are real, not modes. An entry's own damping replaces the file's,
// element by element; a bad value is refused naming the item and the range.
TEST(FeRotor, RayleighShaftDampingGivesEachModeItsClosedFormRatio) {
  const double alpha_per_s = 3.0, beta_s = 2e-5;
  const std::string path =
      write_file("rayleigh_shaft.yaml",
                 "shaft_damping: {mass_proportional_per_s: 3.0, stiffness_proportional_s: 2.0e-5}\n"
                 "shaft:\n  - {elements: 10, length_m: 0.1, outer_diameter_m: 0.05}\n");
  const core::FeRotor rotor = core::load_rotor_file(path);
  const core::RotorMatrices m = core::assemble(rotor);
  const auto modes = core::modes(m, 0.0, 8);
  ASSERT_EQ(modes.size(), 8u);
  for (const auto& mode : modes) {
    const double w = mode.natural_frequency_rad_per_s;
    EXPECT_NEAR(mode.damping_ratio, alpha_per_s / (2.0 * w) + beta_s * w / 2.0, 1e-9) << w;
  }
  EXPECT_GT(modes.front().damping_ratio, 0.0);
  // An entry's own damping for its elements only: half the shaft undamped.
  const core::FeRotor half = core::load_rotor_file(
      write_file("rayleigh_half.yaml",
                 "shaft_damping: {stiffness_proportional_s: 2.0e-5}\n"
                 "shaft:\n  - {elements: 5, length_m: 0.1, outer_diameter_m: 0.05}\n"
                 "  - {elements: 5, length_m: 0.1, outer_diameter_m: 0.05, damping: {stiffness_proportional_s: 0}}\n"));
  const core::RotorMatrices mh = core::assemble(half);
  const int mid = core::dof_index(5, core::kDofX);
  EXPECT_GT(mh.C.block(0, 0, mid, mid).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(mh.C.block(mid + 4, mid + 4, mh.C.rows() - mid - 4, mh.C.rows() - mid - 4).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NE(load_error("shaft_damping: {stiffness_proportional_s: -1e-5}\n"
                       "shaft:\n  - {length_m: 0.5, outer_diameter_m: 0.05}\n")
                .find("shaft_damping key 'stiffness_proportional_s': value -1e-5 is out of range; accepted: [0, inf)"),
            std::string::npos)
      << load_error(
             "shaft_damping: {stiffness_proportional_s: -1e-5}\nshaft:\n  - {length_m: 0.5, outer_diameter_m: 0.05}\n");
}

// The Campbell diagram and the critical speeds' grid solve each speed alone,
// on any number of threads: the same values, bit for bit, as one thread and
// as modes() at each speed; a failure on a thread reaches the caller.
TEST(FeRotor, CampbellIsTheSameAtAnyJobs) {
  const core::RotorMatrices m = core::assemble(ross_example());
  const std::vector<double> speeds = {0.0, 100.0, 200.0, 300.0, 400.0, 500.0, 600.0};
  const auto one = core::campbell(m, speeds, 4, 1);
  const auto three = core::campbell(m, speeds, 4, 3);
  ASSERT_EQ(one.size(), speeds.size());
  ASSERT_EQ(three.size(), speeds.size());
  for (std::size_t s = 0; s < speeds.size(); ++s) {
    const auto alone = core::modes(m, speeds[s], 4);
    ASSERT_EQ(one[s].size(), 4u) << speeds[s];
    ASSERT_EQ(three[s].size(), 4u) << speeds[s];
    for (std::size_t k = 0; k < 4; ++k) {
      EXPECT_EQ(three[s][k].damped_frequency_rad_per_s, one[s][k].damped_frequency_rad_per_s) << speeds[s];
      EXPECT_EQ(three[s][k].damping_ratio, one[s][k].damping_ratio) << speeds[s];
      EXPECT_EQ(three[s][k].whirl, one[s][k].whirl) << speeds[s];
      EXPECT_EQ(alone[k].damped_frequency_rad_per_s, one[s][k].damped_frequency_rad_per_s) << speeds[s];
    }
  }
  const auto serial = core::critical_speeds(m, 4, 400.0, 40, 1);
  const auto parallel = core::critical_speeds(m, 4, 400.0, 40, 2);
  ASSERT_EQ(serial.size(), 4u);
  ASSERT_EQ(parallel.size(), serial.size());
  for (std::size_t k = 0; k < serial.size(); ++k) {
    EXPECT_EQ(parallel[k].speed_rad_per_s, serial[k].speed_rad_per_s);
    EXPECT_EQ(parallel[k].mode_index, serial[k].mode_index);
  }
  core::RotorMatrices massless = m;
  massless.M.setZero();
  EXPECT_THROW(core::campbell(massless, speeds, 4, 3), std::invalid_argument);
  EXPECT_THROW(core::critical_speeds(m, 4, 400.0, 0, 2), std::invalid_argument);
}

// for_each_index runs every index once at any number of jobs, and a failure
// on a thread other than the caller's reaches the caller (each index sleeps
// a millisecond, so the other threads take some).
TEST(ForEachIndex, AFailureOnAThreadReachesTheCaller) {
  for (const unsigned jobs : {1u, 2u, 5u}) {
    std::vector<int> runs(40, 0);
    core::for_each_index(40, jobs, [&runs](int i) { ++runs[static_cast<std::size_t>(i)]; });
    EXPECT_EQ(std::count(runs.begin(), runs.end(), 1), 40) << jobs;
  }
  const std::thread::id caller = std::this_thread::get_id();
  std::atomic<int> others{0};
  auto on_other_threads_fails = [&](int) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (std::this_thread::get_id() != caller) {
      ++others;
      throw std::runtime_error("failed on a worker");
    }
  };
  EXPECT_THROW(core::for_each_index(20, 4, on_other_threads_fails), std::runtime_error);
  EXPECT_GT(others.load(), 0);
}
