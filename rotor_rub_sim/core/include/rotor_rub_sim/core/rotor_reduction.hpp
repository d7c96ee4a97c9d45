/// @file
/// A flexible rotor reduced to no more than a scene needs: the rub station's
/// lateral displacement kept as a physical coordinate, the rest of the shaft
/// in a few modes (Craig-Bampton), in coordinates where the station's mass
/// is uncoupled from the modes.
///
/// The basis (columns of Psi, full DOFs = Psi q_cb):
/// * two constraint modes: the shaft's static shape under a unit x (and y)
///   displacement of the station, every other DOF free (with anisotropic
///   bearings, the mean of the two planes' static shapes);
/// * interior shapes, zero at the station: the static correction that turns
///   that mean into either plane's own ((psi_x - psi_y) / 2, added in one
///   plane and taken away in the other), and the fixed-interface modes (the
///   shaft's modes with the station held) of both planes, lowest frequency
///   first (the correction at its Rayleigh quotient), M-orthonormalised, a
///   shape already in the span left out.
/// Every planar shape (x, beta) comes with its twin turned 90 deg about the
/// axis (y = x, alpha = -beta), so each plane's basis holds both planes'
/// static shapes and modes. The reduced mass matrix is then isotropic, so
/// the contact sees one station mass whatever the direction. K, C and G are
/// the rotor's own (cross-coupled and anisotropic bearings included),
/// projected: the reduction is exact as the shapes are added; without
/// cross-coupling away from the station the station's static stiffness is
/// exact once the static correction is in (isotropic bearings: from 1
/// planar mode, the planes' shapes coincide and the basis is
/// Craig-Bampton's).
///
/// Then q_cb = [u, eta] is changed to q = [u, xi] with
/// eta = xi - M_ee^-1 M_eu u, which makes the mass block-diagonal:
/// M = diag(m_st I_2, I), m_st = the Schur complement M_uu - M_ue M_ee^-1 M_eu
/// [kg]. A contact force on the station enters the u rows alone (the
/// transformation leaves [f; 0] unchanged), so the station moves as a point
/// of mass m_st under the contact and the shaft's elastic and modal forces:
/// the Jeffcott's picture, with the modes' coordinates coupled through K, C
/// and G only. planar_modes = 1 keeps the station alone (Guyan's reduction):
/// a one-disk rotor's Jeffcott, whose mass is the disk's plus the shaft's
/// share (17/35 of a pinned uniform shaft's, Rayleigh's).
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "rotor_rub_sim/core/fe_rotor.hpp"

namespace rotor_rub::core {

struct ReducedRotor {
  int station_node = 0;
  int planar_modes = 1;          ///< per plane: the station, and planar_modes - 1 interior shapes
  RotorMatrices matrices;        ///< M, K, C, G in q = [u_x, u_y, xi...] (size())
  Eigen::MatrixXd expansion;     ///< full FE DOFs = expansion * q (dofs() x size())
  double station_mass_kg = 0.0;  ///< m_st: M = diag(m_st, m_st, I)
  std::vector<double> node_z_m;  ///< each node's position along the shaft [m] (FeRotor::node_z_m)
  int support_nodes = 0;         ///< the full DOFs' (FeRotor::support_nodes)
  /// The rotor's weight per unit gravity along -y, projected: E^T M t_y [kg],
  /// t_y the rigid translation along y in the full DOFs (the consistent
  /// load of the distributed mass: nodal forces and, at the ends of
  /// elements, moments). Gravity g along -y loads q with -g unit_weight_kg.
  Eigen::VectorXd unit_weight_kg;
  int size() const { return 2 * planar_modes; }
  static constexpr int kStationX = 0;    ///< u_x [m]
  static constexpr int kStationY = 1;    ///< u_y [m]
  static constexpr int kFirstModal = 2;  ///< xi [sqrt(kg) m]: mass-normalised modal coordinates
};

/// The most planar modes a rotor has: its planar DOFs (x, beta per shaft
/// node, x per support node).
inline int max_planar_modes(const FeRotor& rotor) { return 2 * rotor.nodes() + rotor.support_nodes(); }

/// The reduction of one assembled rotor at one station, its shapes built
/// once up to most_planar_modes (the held rotor's two eigensolves and the
/// orthonormalisation: the cost), then reduced to any count up to that. The
/// shapes of n planar modes are the first n of any larger count's, so
/// reduce(n) is reduce_rotor(..., n) to the bit (test_rotor_reduction,
/// OneBasisReducesToEveryCountAsItsOwnReductionDoes): a search over counts
/// (rotor_planar_modes auto, the truncation study) pays the eigensolves once.
class RotorReduction {
 public:
  /// Throws std::invalid_argument naming the value and the accepted range
  /// (a station on no node, most_planar_modes out of [1,
  /// max_planar_modes(rotor)]) or when the rotor with its station held
  /// cannot stand.
  RotorReduction(const FeRotor& rotor, const RotorMatrices& m, int station_node, int most_planar_modes);
  /// The rotor reduced to planar_modes in [1, most_planar_modes()].
  /// std::invalid_argument naming the value and the range outside it, or
  /// when the reduced mass is not diag(m_st, m_st, I) (reduce_rotor).
  ReducedRotor reduce(int planar_modes) const;
  int most_planar_modes() const { return static_cast<int>(planar_.cols()); }

 private:
  int station_node_;
  RotorMatrices m_;
  std::vector<double> node_z_m_;
  std::vector<int> x_plane_, y_plane_;  // the planar indices' full DOFs: (x, beta) and their twins (y, alpha)
  std::vector<double> twin_sign_;       // a twin's value is twin_sign times its planar shape's
  Eigen::MatrixXd planar_;              // the planar shapes (x, beta per node), in order
};

/// Reduces the assembled rotor m (of `rotor`) at station_node to planar_modes
/// per plane, in [1, max_planar_modes(rotor)]. Throws std::invalid_argument
/// naming the value and the accepted range (a station on no node, a count
/// out of range), or when the rotor with its station held cannot stand (no
/// bearing to carry it: a singular stiffness).
ReducedRotor reduce_rotor(const FeRotor& rotor, const RotorMatrices& m, int station_node, int planar_modes);

/// The modes of a reduced rotor at speed Omega, their shapes expanded to the
/// full FE DOFs (whirl judged there): as modes() for the full model.
std::vector<Mode> modes(const ReducedRotor& r, double speed_rad_per_s, int count);

/// D(w) = K - w^2 M + i w (C + w G): the steady response to forces turning
/// at w is Q = D^-1 F (q = Re(Q e^{i w t})).
Eigen::MatrixXcd dynamic_stiffness(const RotorMatrices& m, double w_rad_per_s);
/// The complex amplitudes F of the unbalances' forces at speed w: m e w^2
/// e^{i phase} at each node's x and -i times that at its y (a forward force).
/// Throws std::invalid_argument for a node out of range (the shaft's nodes:
/// dofs less 2 per support node, over 4).
Eigen::VectorXcd unbalance_forces(int dofs, const std::vector<RotorUnbalance>& unbalances, double w_rad_per_s,
                                  int support_nodes = 0);

/// The steady response to unbalances turning with the spin at speed w (spin
/// angle 0 at t = 0): q = Re(Q e^{i w t}) with (K - w^2 M + i w (C + w G)) Q =
/// F, F = m e w^2 e^{i phase} (1, -i) at each unbalance's node (x, y), in the
/// full FE DOFs. Throws std::invalid_argument for a node out of range.
Eigen::VectorXcd unbalance_response(const RotorMatrices& m, const std::vector<RotorUnbalance>& unbalances,
                                    double w_rad_per_s);
/// The same for a reduced rotor (forces projected, the response expanded).
Eigen::VectorXcd unbalance_response(const ReducedRotor& r, const std::vector<RotorUnbalance>& unbalances,
                                    double w_rad_per_s);

/// The full model's unbalance response at some speeds, to judge reduced
/// models by (the modal truncation study, rotor_planar_modes auto): a
/// reduced model's error is the worst distance of its response from the
/// full model's at the watched nodes (x and y) over the speeds, relative to
/// the full model's largest displacement (any node) at each speed.
class ResponseReference {
 public:
  /// Throws std::invalid_argument for a watched node or an unbalance's node
  /// out of range.
  ResponseReference(const FeRotor& rotor, const RotorMatrices& full, std::vector<RotorUnbalance> unbalances,
                    std::vector<double> speeds_rad_per_s, std::vector<int> watched_nodes);
  /// The relative error of r's response (0 without speeds or unbalances).
  double error(const ReducedRotor& r) const;

 private:
  std::vector<RotorUnbalance> unbalances_;
  std::vector<double> speeds_rad_per_s_;
  std::vector<int> watched_dofs_;
  std::vector<Eigen::VectorXcd> full_;  // at each speed
  std::vector<double> largest_m_;       // the full response's largest displacement at each speed
};

}  // namespace rotor_rub::core
