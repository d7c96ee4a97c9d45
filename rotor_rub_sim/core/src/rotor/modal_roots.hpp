// The roots of a rotor's first-order system and their vectors, on which
// fe_rotor.cpp's modes, Campbell diagram and critical speeds are built: the
// mass-normalised first-order matrix, which roots are modes, the dense QR's
// roots refined on the quadratic problem, and the lowest modes by
// shift-invert Arnoldi (Spectra), certified complete, for a large rotor.
#pragma once

#include <Eigen/Core>
#include <Eigen/LU>
#include <cmath>
#include <complex>
#include <optional>
#include <vector>

#include "rotor_rub_sim/core/fe_rotor.hpp"

namespace rotor_rub::core::modal {

/// The first-order matrix [[0, I], [-L^-1 K L^-T, -L^-1 (C + Omega G) L^-T]]
/// in mass-normalised coordinates y = L^T q (M = L L^T); L written to l.
Eigen::MatrixXd first_order_matrix(const RotorMatrices& m, double speed_rad_per_s, Eigen::MatrixXd& l);

/// Roots of modulus at most this are rigid-body motion, never a mode: a rotor
/// with a part that has no stiffness path to the ground (a pedestal carrying a
/// shaft bearing without its own to the ground) has zero roots, which the
/// QR leaves at about sqrt(eps) times the largest (1e-4 rad/s on a 32-DOF
/// rotor on pedestals, RotorSupports.AFreePedestalIsRigidBodyMotionNotADivergence).
/// 1 rpm, as ROSS takes a rigid-body mode; no rotor's elastic mode is that slow.
/// At speed such a free motion's gyroscopic nutation, a frequency in
/// proportion to the speed, is a mode once above it (docs/rotors.md).
/// A free rotor whose largest root is above about 7e6 rad/s (1 rpm / sqrt(eps))
/// can see its zero roots' split pass it and list a slow "mode".
inline constexpr double kRigidBodyBelow_rad_per_s = 2.0 * M_PI / 60.0;

/// Whether a root of it is a mode (an oscillation a cycle can show).
bool oscillatory(std::complex<double> lambda);

/// The oscillatory roots of a first-order matrix by damped frequency, from
/// its eigenvalues alone (the QR without vectors).
std::vector<std::complex<double>> mode_roots(const Eigen::MatrixXd& a);

/// A root of (mu^2 M + mu D + K) q = 0 refined from an estimate lambda, with
/// its right and left vectors; `cluster`: the vectors of earlier roots equal
/// to it (a double root), kept apart.
struct QepVectors {
  Eigen::VectorXcd right, left;  // unit vectors
  bool refined = true;           // false: the iteration failed, the root is the estimate's (or its Rayleigh step's)
};
std::complex<double> refined_qep_root(const Eigen::MatrixXcd& mass, const Eigen::MatrixXcd& damping,
                                      const Eigen::MatrixXcd& stiffness, std::complex<double> lambda,
                                      const std::vector<const QepVectors*>& cluster, QepVectors& v);

/// A mode's root (Im lambda > 0) and its shape q in the physical coordinates.
struct ModeRoot {
  std::complex<double> lambda;
  Eigen::VectorXcd shape;
};

/// The `count` lowest modes by damped frequency from every root of the
/// first-order matrix a (the QR), each refined (refined_qep_root).
std::vector<ModeRoot> refined_mode_roots(const RotorMatrices& m, double speed_rad_per_s, const Eigen::MatrixXd& a,
                                         int count);

/// The distance from the shift sigma (lu: A - sigma I factored) within which
/// every root of A is among those whose eigenvectors (columns of `vectors`,
/// their real span of `found` dimensions) were found: the largest root of
/// (A - sigma I)^-1 with that span deflated, the nearest root left out.
/// Nothing where the span is not of that dimension or not invariant, or the
/// search does not converge.
std::optional<double> complete_within(const Eigen::PartialPivLU<Eigen::MatrixXd>& lu, const Eigen::MatrixXcd& vectors,
                                      Eigen::Index found);

/// The `count` lowest modes by damped frequency (fewer where the rotor has
/// fewer) of the first-order matrix a (l: its mass factor), by shift-invert
/// Arnoldi; nothing where the answer cannot be certified complete and
/// accurate (the caller then takes the dense QR).
std::optional<std::vector<ModeRoot>> lowest_mode_roots(const Eigen::MatrixXd& a, const Eigen::MatrixXd& l, int count);

/// Every mode with a damped frequency up to w_max, lowest first: Arnoldi's
/// lowest ones, ever more until one lies above, else the QR's (unrefined).
std::vector<std::complex<double>> mode_roots_below(const Eigen::MatrixXd& a, const Eigen::MatrixXd& l,
                                                   double w_max_rad_per_s);

}  // namespace rotor_rub::core::modal
