// The lowest modes by shift-invert Arnoldi (modal_roots.hpp) against every
// root by the dense QR, refined: on the rotors a user brings (anisotropic
// bearings, stiffness-proportional damping, an isotropic rotor whose roots
// are double at rest), at rest and at speed; and against the closed form on
// a root twelve-fold.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <complex>
#include <optional>
#include <string>
#include <vector>

#include "rotor/modal_roots.hpp"
#include "rotor_rub_sim/core/fe_rotor.hpp"
#include "rotor_rub_sim/core/rotor_file.hpp"
#include "test_support.hpp"

using namespace rotor_rub;
namespace modal = core::modal;

namespace {

// Arnoldi's roots against the refined QR's, relative: Ritz values converged
// to 1e-12 of 1 / (lambda - sigma), times the roots' condition (6.7e-11
// measured on the anisotropic rig).
constexpr double kSameRoot = 1e-9;
// A shape's distance from its root's eigenspace, both unit: the Ritz
// vectors' residual over the gap to the next root (measured: 4.4e-10 on the
// isotropic rotor at rest, its roots double).
constexpr double kInTheEigenspace = 1e-8;

struct Case {
  const char* file;
  double speed_rad_per_s;
  int count;
};

// The distance of a unit shape x from the eigenspace of a root of
// multiplicity k: from the null space of Q(lambda) = lambda^2 M + lambda (C
// + Omega G) + K, the right singular vectors of its k smallest singular values.
double off_the_eigenspace(const core::RotorMatrices& m, double speed_rad_per_s, std::complex<double> lambda, int k,
                          const Eigen::VectorXcd& x) {
  using Complex = std::complex<double>;
  const Eigen::MatrixXcd q = lambda * lambda * m.M.cast<Complex>() +
                             lambda * (m.C + speed_rad_per_s * m.G).cast<Complex>() + m.K.cast<Complex>();
  const Eigen::BDCSVD<Eigen::MatrixXcd> svd(q, Eigen::ComputeFullV);
  const Eigen::MatrixXcd null = svd.matrixV().rightCols(k);
  const Eigen::VectorXcd u = x.normalized();
  return (u - null * (null.adjoint() * u)).norm();
}

void expect_the_dense_modes(const core::RotorMatrices& m, double speed_rad_per_s,
                            const std::vector<modal::ModeRoot>& arnoldi, int count, const std::string& what) {
  Eigen::MatrixXd l;
  const Eigen::MatrixXd a = modal::first_order_matrix(m, speed_rad_per_s, l);
  // Two more roots than asked: a double root's second copy past the count.
  const std::vector<modal::ModeRoot> dense = modal::refined_mode_roots(m, speed_rad_per_s, a, count + 2);
  ASSERT_EQ(arnoldi.size(), std::min<std::size_t>(dense.size(), count)) << what;
  for (std::size_t i = 0; i < arnoldi.size(); ++i) {
    EXPECT_LE(std::abs(arnoldi[i].lambda - dense[i].lambda), kSameRoot * std::abs(dense[i].lambda))
        << what << ", mode " << i << ": " << arnoldi[i].lambda << " against " << dense[i].lambda;
    int multiplicity = 0;
    for (const modal::ModeRoot& d : dense)
      multiplicity += std::abs(d.lambda - dense[i].lambda) <= 1e-6 * std::abs(dense[i].lambda);
    EXPECT_LE(off_the_eigenspace(m, speed_rad_per_s, dense[i].lambda, multiplicity, arnoldi[i].shape), kInTheEigenspace)
        << what << ", mode " << i << " (a root " << multiplicity << "-fold)";
    // A multiple root's copies have shapes of their own (orthonormal).
    for (std::size_t j = 0; j < i; ++j) {
      if (std::abs(arnoldi[j].lambda - arnoldi[i].lambda) <= 1e-6 * std::abs(arnoldi[i].lambda)) {
        EXPECT_LE(std::abs(arnoldi[j].shape.normalized().dot(arnoldi[i].shape.normalized())), kInTheEigenspace)
            << what << ", modes " << j << " and " << i << " of a multiple root";
      }
    }
  }
}

}  // namespace

// Certified, and the dense path's modes, on the rotors large enough for it
// (a quarter of the first-order size above the roots it asks for).
TEST(ModalRoots, ArnoldiFindsTheDenseQrsLowestModes) {
  const Case cases[] = {
      {"test/data/rotors/anisotropic_rig.yaml", 0.0, 6},     // 204 DOF, kyy/kxx 115
      {"test/data/rotors/anisotropic_rig.yaml", 700.0, 12},  //
      {"config/rotors/ross_rub_rig.yaml", 0.0, 1},           // stiffness-proportional damping
      {"config/rotors/ross_rub_rig.yaml", 1000.0, 6},        // overdamped pairs turned by the spin
      {"test/data/rotors/fine_damped_seal.yaml", 0.0, 6},    // isotropic: every root double
      {"test/data/rotors/fine_damped_seal.yaml", 2000.0, 6},
  };
  for (const Case& c : cases) {
    const core::RotorMatrices m = core::assemble(core::load_rotor_file(test::source_path(c.file)));
    Eigen::MatrixXd l;
    const Eigen::MatrixXd a = modal::first_order_matrix(m, c.speed_rad_per_s, l);
    const std::string what = std::string(c.file) + " at " + std::to_string(c.speed_rad_per_s) + " rad/s";
    const std::optional<std::vector<modal::ModeRoot>> arnoldi = modal::lowest_mode_roots(a, l, c.count);
    ASSERT_TRUE(arnoldi.has_value()) << what << ": not certified";
    expect_the_dense_modes(m, c.speed_rad_per_s, *arnoldi, c.count, what);
  }
}

namespace {

constexpr double kDampingN_s_per_m = 20.0;  // the thirty disks' translations

core::RotorMatrices thirty_disks() {
  const int disks = 30, dofs = 4 * disks;
  core::RotorMatrices m;
  m.M = Eigen::MatrixXd::Identity(dofs, dofs);
  m.K = Eigen::MatrixXd::Zero(dofs, dofs);
  m.C = Eigen::MatrixXd::Zero(dofs, dofs);
  m.G = Eigen::MatrixXd::Zero(dofs, dofs);
  for (int d = 0; d < disks; ++d) {
    const double translation_N_per_m = d < 6 ? 1e6 : 1e6 * (d + 1) * (d + 1);
    const double tilt_rad_per_s = 1e3 * (40 + d);
    for (const int dof : {core::kDofX, core::kDofY}) {
      m.K(4 * d + dof, 4 * d + dof) = translation_N_per_m;
      m.C(4 * d + dof, 4 * d + dof) = kDampingN_s_per_m;
    }
    for (const int dof : {core::kDofAlpha, core::kDofBeta}) {
      m.M(4 * d + dof, 4 * d + dof) = 0.1;
      m.K(4 * d + dof, 4 * d + dof) = 0.1 * tilt_rad_per_s * tilt_rad_per_s;
    }
  }
  return m;
}

}  // namespace

// Thirty disks on their own bearings, no coupling: the first six alike, so
// that the lowest root is twelve-fold (x and y of six disks), the others'
// translations at 7000, 8000, ... rad/s and their tilts far above. A single
// start vector's Krylov space holds one copy in exact arithmetic; Arnoldi
// finds all twelve in rounding, and the deflated check (complete_within)
// certifies it: the twelve lowest modes are twelve copies of the closed
// form's l^2 + c l + k = 0 (m = 1 kg, k = 1e6 N/m, c = 20 N s/m). With a copy
// missing, the next root would stand in its place, or the answer be refused.
TEST(ModalRoots, ATwelveFoldRootIsFoundInEveryCopy) {
  const core::RotorMatrices m = thirty_disks();
  const double c = kDampingN_s_per_m;
  const std::complex<double> expected(-0.5 * c, std::sqrt(1e6 - 0.25 * c * c));
  Eigen::MatrixXd l;
  const Eigen::MatrixXd a = modal::first_order_matrix(m, 0.0, l);
  const std::optional<std::vector<modal::ModeRoot>> arnoldi = modal::lowest_mode_roots(a, l, 12);
  ASSERT_TRUE(arnoldi.has_value()) << "not certified";
  ASSERT_EQ(arnoldi->size(), 12u);
  for (int i = 0; i < 12; ++i) {
    EXPECT_LE(std::abs((*arnoldi)[static_cast<std::size_t>(i)].lambda - expected), kSameRoot * std::abs(expected))
        << "mode " << i;
  }
  // Twelve shapes of their own, each in the translations of the six alike
  // disks (orthonormal: modal_roots.cpp makes a multiple root's so).
  Eigen::MatrixXcd shapes(m.M.rows(), 12);
  for (int i = 0; i < 12; ++i) shapes.col(i) = (*arnoldi)[static_cast<std::size_t>(i)].shape;
  EXPECT_LE((shapes.adjoint() * shapes - Eigen::MatrixXcd::Identity(12, 12)).norm(), kInTheEigenspace);
  for (int d = 0; d < 30; ++d) {
    for (const int dof : {core::kDofX, core::kDofY, core::kDofAlpha, core::kDofBeta}) {
      const bool alike_translation = d < 6 && (dof == core::kDofX || dof == core::kDofY);
      if (!alike_translation) EXPECT_LE(shapes.row(4 * d + dof).norm(), kInTheEigenspace) << "disk " << d;
    }
  }
}

// Given one copy of the twelve-fold root (disk 0's x), the radius within
// which every root was found stops at that root: the other eleven copies are
// the deflated operator's largest roots. (From the first run's start vector
// the deflated run would not see a copy that run missed: its own start.)
TEST(ModalRoots, OneCopyOfAMultipleRootFoundLeavesTheRadiusAtIt) {
  const core::RotorMatrices m = thirty_disks();
  Eigen::MatrixXd l;
  const Eigen::MatrixXd a = modal::first_order_matrix(m, 0.0, l);
  const double sigma = -1.0;  // modal_roots.cpp's shift
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(a - sigma * Eigen::MatrixXd::Identity(a.rows(), a.cols()));
  const double c = kDampingN_s_per_m;
  const std::complex<double> lambda(-0.5 * c, std::sqrt(1e6 - 0.25 * c * c));
  const Eigen::Index n = m.M.rows();
  Eigen::VectorXcd y = Eigen::VectorXcd::Zero(2 * n);  // [L^T q; lambda L^T q], q = disk 0's x, L = I there
  y(core::kDofX) = 1.0;
  y(n + core::kDofX) = lambda;
  const std::optional<double> radius = modal::complete_within(lu, y, 2);  // the pair: two real dimensions
  ASSERT_TRUE(radius.has_value());
  EXPECT_LE(*radius, std::abs(lambda - sigma) * (1.0 + 1e-5));
  // And with all twelve copies given (x and y of the six alike disks), the
  // radius reaches the next root, at 7000 rad/s.
  Eigen::MatrixXcd copies = Eigen::MatrixXcd::Zero(2 * n, 12);
  for (int k = 0; k < 12; ++k) {
    const Eigen::Index dof = 4 * (k / 2) + (k % 2 == 0 ? core::kDofX : core::kDofY);
    copies(dof, k) = 1.0;
    copies(n + dof, k) = lambda;
  }
  const std::optional<double> all = modal::complete_within(lu, copies, 24);
  ASSERT_TRUE(all.has_value());
  EXPECT_GT(*all, 6000.0);
}

// Which roots are modes: one that completes a cycle before decaying, or
// growing, by 1 / eps (Im > 0.174 |Re|); so a flutter that grows slower than
// that is listed (a Campbell diagram shows the instability), a root that
// grows by 1e15 in a turn is not, as one that decays so is not.
TEST(ModalRoots, ARootIsAModeWhenItTurnsBeforeItGrowsOrDecaysPastRounding) {
  EXPECT_TRUE(modal::oscillatory({0.0, 100.0}));      // undamped
  EXPECT_TRUE(modal::oscillatory({-570.0, 100.0}));   // decays by exp(2 pi 5.7) = 3.6e15 in a cycle
  EXPECT_TRUE(modal::oscillatory({570.0, 100.0}));    // a flutter growing as fast
  EXPECT_FALSE(modal::oscillatory({-580.0, 100.0}));  // past 1 / eps = 4.5e15: overdamped
  EXPECT_FALSE(modal::oscillatory({580.0, 100.0}));   // grows past it: no oscillation to see
  EXPECT_FALSE(modal::oscillatory({5.0, 0.0}));       // real: a static divergence
  EXPECT_FALSE(modal::oscillatory({1e-7, 1e-7}));     // a rigid-body root
}
