/// @file
/// Stability of the synchronous full annular rub (steady_response.hpp's
/// FullRub) of the Jeffcott rotor under the prescribed drive at a constant
/// speed w, with the rigid contact (the switching and iteration methods'
/// contact: the rotor held on the bore, sliding forward, the friction f N
/// against the slip). In the frame turning at w the full rub is an
/// equilibrium; its linearisation there decides whether it holds.
///
/// Coordinates in the turning frame (u = z e^{-i w t}, complex): the stator
/// u_s, the contact angle theta (the rotor at u_r = u_s + C e^{i theta}),
/// and their rates; the normal force N is the constraint's multiplier,
/// eliminated. Rotor and stator:
///   m (u_r'' + 2 i w u_r' - w^2 u_r) + c (u_r' + i w u_r) + k u_r = F - N (1 + i f) n,
///   m_s (u_s'' + 2 i w u_s' - w^2 u_s) + c_s (u_s' + i w u_s) + k_s u_s = N (1 + i f) n,
/// n = e^{i theta}, F = m e w^2 e^{i beta}. A rigid stator is u_s = 0.
/// The state is [q; q'] with q = (x_s, y_s, theta) (elastic) or (theta)
/// (rigid): its Jacobian at the equilibrium by central differences, and its
/// eigenvalues. Rigid stator, in closed form (docs/steady_response.md):
///   m C lambda^2 + (c + 2 f m w) C lambda + |F| (cos phi - f sin phi) = 0,
/// phi = theta - beta the contact's angle from the unbalance: stable iff
/// cos phi - f sin phi > 0 (cos b + f sin b > 0 with b = -phi, the
/// unbalance's angle from the contact). Valid while the slip stays forward
/// (w (C + R_r) > 0) and N > 0; gravity must be 0, as for FullRub.
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <vector>

#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/steady_response.hpp"

namespace rotor_rub::core {

/// One branch of the full rub at a speed, linearised.
struct FullRubStability {
  FullRub rub;  ///< the equilibrium (inertial positions at spin angle 0)
  /// [q; q'] in the turning frame, q = (x_s, y_s, theta) elastic, (theta)
  /// rigid [m, rad, m/s, rad/s]: d/dt of it at the equilibrium.
  Eigen::MatrixXd jacobian;
  /// Its eigenvalues [1/s], the largest real part first: e^{lambda t} in the
  /// turning frame (a perturbation there at Im lambda whirls at w +- Im
  /// lambda in the casing's frame).
  std::vector<std::complex<double>> eigenvalues;
  /// Every eigenvalue's real part below 0.
  bool stable() const { return !eigenvalues.empty() && eigenvalues.front().real() < 0.0; }
};

/// Every branch of synchronous_full_rub(p, w), linearised. Throws
/// std::invalid_argument for gravity or a motor drive (not modelled here).
std::vector<FullRubStability> full_rub_stability(const ModelParameters& p, double w_rad_per_s);

/// The rigid stator's two eigenvalues in closed form (see above), for a
/// branch of synchronous_full_rub.
std::vector<std::complex<double>> rigid_full_rub_eigenvalues(const ModelParameters& p, double w_rad_per_s,
                                                             const FullRub& rub);

/// The turning frame's accelerations at a state [q; q'] (as jacobian's),
/// and the normal force there [N]: the equations above solved for q'' and
/// N. For tests and the linearisation.
Eigen::VectorXd full_rub_rates(const ModelParameters& p, double w_rad_per_s, const Eigen::VectorXd& state,
                               double* normal_force_N = nullptr);

}  // namespace rotor_rub::core
