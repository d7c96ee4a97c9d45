/// @file
/// Stability of the synchronous full annular rub under the prescribed drive
/// at a constant speed w, with the rigid contact (the switching and
/// iteration methods' contact: the rotor held on the bore, sliding forward,
/// the friction f N against the slip), for the Jeffcott rotor
/// (steady_response.hpp's FullRub) and for an isotropic flexible rotor,
/// full or reduced (rotor_steady_response.hpp). In the frame turning at w
/// the full rub is an equilibrium; its linearisation there decides whether
/// it holds.
///
/// A rotor of coordinates v (the Jeffcott's x, y; an FE model's DOFs; a
/// reduced rotor's q) is isotropic when its matrices commute with the
/// rotation's generator J (each pair (x, y), (alpha, beta) turning as
/// (-y, x); J^2 = -I): with z = R(w t) v, R = exp(w t J),
///   M (v'' + 2 w J v' - w^2 v) + (C + w G)(v' + w J v) + K v = w^2 a + B f_c,
/// a the unbalances' force at spin angle 0 per unit w^2 (constant in the
/// turning frame), f_c = -N (n + f J n) the contact force at the station's
/// rows B, n = (cos theta, sin theta). The station is on the bore: v_st =
/// u_s + C n, u_s the stator, whose own equation is
///   m_s (u_s'' + 2 w J u_s' - w^2 u_s) + c_s (u_s' + w J u_s) + k_s u_s = N (n + f J n)
/// (a rigid stator: u_s = 0). N is the constraint's multiplier, eliminated:
/// the state is [q; q'], q = (the coordinates but the station's, u_s when
/// elastic, theta); its Jacobian at the equilibrium (analytic: linear but in
/// theta; the penalty contact's by central differences), and its
/// eigenvalues after balancing. The Jeffcott on a rigid stator, in closed form
/// (docs/steady_response.md):
///   m C lambda^2 + (c + 2 f m w) C lambda + |F| (cos phi - f sin phi) = 0,
/// phi = theta - beta: stable iff cos phi - f sin phi > 0. Valid while the
/// slip stays forward (w (C + R_r) > 0) and N > 0; no gravity.
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <vector>

#include "rotor_rub_sim/core/fe_rotor.hpp"
#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/rotor_reduction.hpp"
#include "rotor_rub_sim/core/rotor_steady_response.hpp"
#include "rotor_rub_sim/core/steady_response.hpp"

namespace rotor_rub::core {

/// A linear isotropic rotor as the turning frame sees it (see above).
struct TurningRotor {
  RotorMatrices matrices;            ///< M, K, C, G in the coordinates v
  Eigen::MatrixXd turn;              ///< J: the rotation's generator in v (J^2 = -I)
  Eigen::VectorXd unbalance_kg_m;    ///< a: the unbalances' force at spin angle 0 per unit w^2 [kg m]
  int station_x = 0, station_y = 1;  ///< the station's rows in v
};

/// The Jeffcott rotor of p (m, k, c, e, beta): 2 coordinates.
TurningRotor turning_rotor(const ModelParameters& p);
/// p's stator (rigid, or its mass, stiffness and damping).
StationStator station_stator(const ModelParameters& p);
/// A full FE model (assemble) with its unbalances and station node. Throws
/// std::invalid_argument when not isotropic (bearings kxx != kyy, ...).
TurningRotor turning_rotor(const RotorMatrices& m, const std::vector<RotorUnbalance>& unbalances, int station_node);
/// A reduced rotor of the full model m (reduce_rotor): J projected onto its
/// basis, which must hold the rotation (an isotropic rotor's twin planes).
TurningRotor turning_rotor(const ReducedRotor& r, const RotorMatrices& m,
                           const std::vector<RotorUnbalance>& unbalances);

/// The penalty method's contact in place of the rigid one (contact_law.hpp):
/// N = k_c p + c_c p' while pressed (p the overlap |u_r - u_s| - C), the
/// friction f N against the forward slip. The station is then free: q is
/// every coordinate, and the stator's when elastic.
struct PenaltyContact {
  double stiffness_N_per_m = 0.0;  ///< k_c
  double damping_N_s_per_m = 0.0;  ///< c_c
};

/// One full rub of a turning rotor, linearised.
struct FullRubStability {
  double normal_force_N = 0.0;
  std::complex<double> station_m, stator_m;  ///< the station and the stator at spin angle 0
  /// [q; q'] at the equilibrium (q: the coordinates but the station's, the
  /// stator's x, y when elastic, theta; with the penalty contact every
  /// coordinate and the stator's), and d/dt of it there.
  Eigen::VectorXd state;
  Eigen::MatrixXd jacobian;
  /// Its eigenvalues [1/s], the largest real part first: e^{lambda t} in the
  /// turning frame (a disturbance at Im lambda there whirls at w +- Im
  /// lambda in the casing's frame).
  std::vector<std::complex<double>> eigenvalues;
  /// Every eigenvalue's real part below 0.
  bool stable() const { return !eigenvalues.empty() && eigenvalues.front().real() < 0.0; }
};

/// The turning frame's accelerations at a state [q; q'] and the normal force
/// there [N] (the equations above solved for q'' and N).
Eigen::VectorXd full_rub_rates(const TurningRotor& rotor, const StationStator& stator, double clearance_m,
                               double friction_coefficient, double w_rad_per_s, const Eigen::VectorXd& state,
                               double* normal_force_N = nullptr, const PenaltyContact* penalty = nullptr);

/// The full rub near a guess (the station, the stator and N of a closed
/// form), found by Newton on the turning frame's rest point, then
/// linearised. Throws std::runtime_error when Newton does not converge.
FullRubStability linearised_full_rub(const TurningRotor& rotor, const StationStator& stator, double clearance_m,
                                     double friction_coefficient, double w_rad_per_s, const Eigen::VectorXd& guess,
                                     const PenaltyContact* penalty = nullptr);

/// The eigenvalues of a, the largest real part first, after balancing it
/// (a diagonal similarity; a stiff rotor's Jacobian spans many decades).
std::vector<std::complex<double>> balanced_eigenvalues(const Eigen::MatrixXd& a);
/// x(t) of x' = a x from x0, through a's balanced eigendecomposition (a
/// diagonalisable; the runs' tests compare with it).
Eigen::VectorXd linear_response(const Eigen::MatrixXd& a, const Eigen::VectorXd& x0, double t_s);

/// Every branch of the Jeffcott's synchronous_full_rub(p, w), linearised:
/// with the rigid contact, or with the penalty method's (p's k_c and c_c:
/// its rest point the rigid one's with the bore moved out by N / k_c,
/// polished by Newton). Throws std::invalid_argument for gravity or a motor
/// drive.
std::vector<FullRubStability> full_rub_stability(const ModelParameters& p, double w_rad_per_s,
                                                 bool penalty_contact = false);

/// Every branch of a flexible rotor's full rub (the full FE model, or a
/// reduced one when `reduced` is given), from rotor_steady_response.hpp's
/// closed form of the full model, polished by Newton on the reduced one.
std::vector<FullRubStability> full_rub_stability(const RotorMatrices& m, int station_node,
                                                 const std::vector<RotorUnbalance>& unbalances,
                                                 const StationStator& stator, double clearance_m,
                                                 double friction_coefficient, double w_rad_per_s,
                                                 const ReducedRotor* reduced = nullptr);

/// The Jeffcott's two eigenvalues on a rigid stator in closed form (see
/// above), for a branch of synchronous_full_rub.
std::vector<std::complex<double>> rigid_full_rub_eigenvalues(const ModelParameters& p, double w_rad_per_s,
                                                             const FullRub& rub);

}  // namespace rotor_rub::core
