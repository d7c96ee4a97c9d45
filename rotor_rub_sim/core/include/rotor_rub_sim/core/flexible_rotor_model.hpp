/// @file
/// The reduced flexible rotor's free forces (rotor_reduction.hpp) in the
/// form the contact methods take the Jeffcott's (model.hpp): the force on the
/// rub station, a point of mass m_st, and the accelerations of the modal
/// coordinates, which no contact force reaches (docs/rotor_theory.md, the seam).
///
/// In q = [u, xi] (M = diag(m_st I, I)):
///   M q'' = -K q - (C + w G) q' + f(phi, w, A) + [F_contact; 0],
///   f = w^2 (a cos phi + b sin phi) + A (a sin phi - b cos phi),
/// a and b the unbalances' forces (projected) at spin angle 0 and a quarter
/// turn on, per unit w^2: each unbalance m e at angle beta pushes its node by
/// m e (w^2 (cos, sin) + A (sin, -cos))(phi + beta), the Jeffcott's law;
/// with gravity, f also holds the weight, -g E^T M t_y (ReducedRotor::
/// unit_weight_kg), constant. u is the station's displacement in the
/// casing's frame, where the bearings sit.
///
/// Under a motor drive the spin is a state and the unbalances' lever
/// couples it to the shaft (Lagrange's equations with each unbalance a point
/// mass m e off its node, as the Jeffcott's, model.hpp):
///   M q'' = -K q - (C + w G) q' + w^2 (a cos phi + b sin phi) + A h + F_c,
///   J A   = T_m + R_r F_t + h^T q'',   h = a sin phi - b cos phi,
/// J the rotating train's polar inertia about the shaft axis (the scene's
/// rotor_polar_inertia_kg_m2). Eliminating xi'' = F_xi + A h_xi (no contact
/// force reaches the modes) leaves the Jeffcott's form at the station
/// (station_model.hpp's SpinCoupling): lever h_u / m_st, J_eff = J - h^T M^-1 h,
/// extra torque h_xi . F_xi; the modes then take A h_xi (add_spin_share),
/// and at an impact the spin's jump dw, dxi' = h_xi dw.
#pragma once

#include <Eigen/Dense>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/model.hpp"
#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/rotor_reduction.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

/// xi, xi'' or xi''' of a flexible rotor (at most kMaxModalCoordinates).
using ModalVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxModalCoordinates, 1>;

/// How well a flexible rotor's reduction holds its unbalance response, as
/// read at the start (the run's summary and log): ResponseReference::error
/// at the rub station and the file's probe nodes over the scene's speeds.
struct TruncationReport {
  bool chosen = false;     ///< rotor_planar_modes auto chose the count
  double tolerance = 0.0;  ///< auto's bound (chosen only)
  /// Relative to the full model's largest displacement; NaN: not judged (no
  /// unbalance in the file, or no speed above 0).
  double response_error = std::numeric_limits<double>::quiet_NaN();
  double min_speed_rad_per_s = 0.0;  ///< the speeds judged: [min, max]
  double max_speed_rad_per_s = 0.0;  ///< see min_speed_rad_per_s
  /// The full model's critical speeds in [min, max] whose flanks were judged too (a run-up's).
  std::vector<double> critical_speeds_rad_per_s;
};

/// One line on a reduction, as the runner and the node log it: "14 planar
/// modes (auto, rotor_truncation_tolerance 0.001): unbalance response within
/// 6.066e-05 of the full model's largest displacement at 150 .. 330 rad/s and
/// the flanks of its 2 critical speeds there (rub station and probe nodes)".
std::string to_string(long planar_modes, const TruncationReport& t);

class FlexibleRotorModel {
 public:
  /// Throws std::invalid_argument for an unbalance on no node or a rotor of
  /// more than kMaxPlanarModes planar modes, or a probe node on no node.
  /// contact_radius_m: the rotating surface's radius at the station (0: not
  /// given); probe_node: the node the probes read (-1: the station);
  /// gravity_m_per_s2 along -y on every mass of the rotor (a horizontal
  /// machine; ReducedRotor::unit_weight_kg).
  FlexibleRotorModel(const ReducedRotor& rotor, const std::vector<RotorUnbalance>& unbalances,
                     double contact_radius_m = 0.0, int probe_node = -1, double gravity_m_per_s2 = 0.0);

  int modal_size() const { return static_cast<int>(k_.rows()) - 2; }  ///< n: xi's entries
  double station_mass_kg() const { return station_mass_kg_; }
  double contact_radius_m() const { return contact_radius_m_; }
  int probe_node() const { return probe_node_; }

  /// The displacement of the probe node [m] (casing frame) for the station
  /// at u [m] (casing frame) and the modal block modal = [xi; xi']: the
  /// expansion's x and y rows there, times q = [u; xi].
  template <class Modal>
  Vec2 probe_displacement(const Vec2& u, const Eigen::MatrixBase<Modal>& modal) const {
    const int n = modal_size();
    return probe_rows_.leftCols<2>() * u + probe_rows_.rightCols(n) * modal.head(n);
  }
  const ReducedRotor& rotor() const { return rotor_; }
  /// The same rotor with the unbalances added (a blade lost: the lost
  /// mass's unbalance turned by pi). Only the forcing (a, b) and the
  /// unbalances' weight change, not the basis or the matrices, so a run's
  /// state carries over (Simulation::change_parameters; test
  /// BladeLossOnTheSealRotorSettlesOnItsClosedForm). Throws
  /// std::invalid_argument for a node out of range.
  FlexibleRotorModel with_unbalances(const std::vector<RotorUnbalance>& added) const;
  /// The nodes that carry a disk (the element file's; empty for imported
  /// matrices, which name none): where a blade can be lost.
  const std::vector<int>& disk_nodes() const { return disk_nodes_; }
  /// Sets them (load_flexible_rotor).
  void set_disk_nodes(std::vector<int> nodes) { disk_nodes_ = std::move(nodes); }
  /// The reduction's truncation error as judged at the start (load_flexible_rotor).
  const TruncationReport& truncation() const { return truncation_; }
  /// Sets it (load_flexible_rotor).
  void set_truncation(const TruncationReport& t) { truncation_ = t; }
  int nodes() const { return static_cast<int>(rotor_.node_z_m.size()); }  ///< shaft nodes

  /// The lateral displacement of every node [m] (casing frame; node order)
  /// for the station at u and the modal block [xi; xi'], written to out
  /// (resized to nodes(): no allocation once it has the capacity).
  template <class Modal>
  void node_displacements(const Vec2& u, const Eigen::MatrixBase<Modal>& modal, std::vector<Vec2>& out) const {
    const int n = modal_size();
    out.resize(static_cast<std::size_t>(nodes()));
    for (int node = 0; node < nodes(); ++node) {
      const auto rows = node_rows_.middleRows<2>(2 * node);
      out[static_cast<std::size_t>(node)] = rows.leftCols<2>() * u + rows.rightCols(n) * modal.head(n);
    }
  }

  /// Every force but the contact's at the station's position and velocity
  /// u, u_dot [m, m/s] (the casing's frame) and the modal block modal =
  /// [xi; xi'] (2 n), for the unbalance's direction unbalance_dir (cos, sin)
  /// of the spin angle (the scene's unbalance_phase_rad added: it turns every
  /// unbalance), the spin speed w and acceleration A: the station's [N],
  /// returned, and the modal accelerations xi'' (n), written to xi_acc.
  template <class Modal, class Out>
  Vec2 free_loads(const Vec2& u, const Vec2& u_dot, const Eigen::MatrixBase<Modal>& modal, const Vec2& unbalance_dir,
                  double w, double A, const Eigen::MatrixBase<Out>& xi_acc) const {
    const int n = modal_size();
    Reduced q(n + 2), q_dot(n + 2), f(n + 2);
    q.head<2>() = u;
    q.tail(n) = modal.head(n);
    q_dot.head<2>() = u_dot;
    q_dot.tail(n) = modal.tail(n);
    const double c = unbalance_dir.x(), s = unbalance_dir.y();
    f.noalias() = -k_ * q;
    f.noalias() -= c_ * q_dot;
    f.noalias() -= w * (g_ * q_dot);
    f += (w * w * c + A * s) * a_ + (w * w * s - A * c) * b_;
    f += weight_;
    const_cast<Eigen::MatrixBase<Out>&>(xi_acc) = f.tail(n);
    return f.head<2>();
  }

  /// The free loads' partial derivatives at a fixed state, for an implicit
  /// integrator's closed-form Jacobian (penalty_system.hpp, checked against
  /// differences by test_penalty_jacobian.cpp): by q = [u; xi] -K, by q'
  /// -(C + w G); the station's rows are forces, the block's accelerations.
  const Eigen::MatrixXd& stiffness_matrix() const { return k_; }
  const Eigen::MatrixXd& damping_matrix() const { return c_; }     ///< C: see stiffness_matrix()
  const Eigen::MatrixXd& gyroscopic_matrix() const { return g_; }  ///< G: see stiffness_matrix()
  /// The free loads' partial time rate at a fixed state under the
  /// prescribed drive (A constant on a speed segment): the unbalances turning
  /// (phi' = w, w' = A) and w G q' growing,
  ///   -A G q' + 3 w A (a cos phi + b sin phi) + w^3 (b cos phi - a sin phi),
  /// the station's [N/s] returned, the block's (n) written to xi_rate.
  template <class Modal, class Out>
  Vec2 free_load_time_rate(const Vec2& u_dot, const Eigen::MatrixBase<Modal>& modal, const Vec2& unbalance_dir,
                           double w, double A, const Eigen::MatrixBase<Out>& xi_rate) const {
    const int n = modal_size();
    Reduced q_dot(n + 2), f(n + 2);
    q_dot.head<2>() = u_dot;
    q_dot.tail(n) = modal.tail(n);
    const double c = unbalance_dir.x(), s = unbalance_dir.y();
    f.noalias() = -A * (g_ * q_dot);
    f += (3.0 * w * A * c - w * w * w * s) * a_ + (3.0 * w * A * s + w * w * w * c) * b_;
    const_cast<Eigen::MatrixBase<Out>&>(xi_rate) = f.tail(n);
    return f.head<2>();
  }

  /// Under a motor drive: the spin coupling (model.hpp) at the unbalance's
  /// direction, given xi'' without the spin's share (free_loads with A = 0,
  /// F_xi) and the train's polar inertia J [kg m^2]. Under gravity the
  /// unbalances' own weight turns the spin (their pendulum torque, -g sum
  /// m e cos(phi + beta)): the FE model's weight, which reaches the spin
  /// through h^T q'', acts at the nodes, and the unbalances' masses are not
  /// in M (on the one-node Jeffcott the two cancel, as the Jeffcott's weight
  /// at its mass centre has no torque). Throws std::logic_error when J_eff
  /// = J - h^T M^-1 h is not positive (the scene's validation keeps it well
  /// above: validate_scene's bound).
  template <class Modal>
  SpinCoupling spin_coupling(const Vec2& unbalance_dir, const Eigen::MatrixBase<Modal>& free_xi_acc,
                             double polar_inertia_kg_m2) const {
    const int n = modal_size();
    Reduced h(n + 2);
    lever(unbalance_dir, h);
    SpinCoupling sc;
    sc.lever_m = h.head<2>() / station_mass_kg_;
    const double j_eff = polar_inertia_kg_m2 - h.head<2>().squaredNorm() / station_mass_kg_ - h.tail(n).squaredNorm();
    if (!(j_eff > 0.0)) throw std::logic_error("flexible rotor: the spin's effective inertia is not positive");
    sc.inv_inertia_per_kg_m2 = 1.0 / j_eff;
    sc.extra_torque_N_m = h.tail(n).dot(free_xi_acc.head(n)) -
                          (unbalance_dir.x() * pendulum_N_m_.x() - unbalance_dir.y() * pendulum_N_m_.y());
    return sc;
  }
  /// The torque the rotor's lateral motion puts on the spin [N m]: h^T q''
  /// less the unbalances' pendulum torque under gravity (spin_coupling()),
  /// for the station's acceleration u_acc [m/s^2] and the modes' xi_acc (n).
  /// Under the prescribed drive the drive supplies it besides J A - R_r F_t
  /// (the Jeffcott's e F . u).
  template <class Modal>
  double lateral_torque_N_m(const Vec2& unbalance_dir, const Vec2& u_acc,
                            const Eigen::MatrixBase<Modal>& xi_acc) const {
    const int n = modal_size();
    Reduced h(n + 2);
    lever(unbalance_dir, h);
    return h.head<2>().dot(u_acc) + h.tail(n).dot(xi_acc.head(n)) -
           (unbalance_dir.x() * pendulum_N_m_.x() - unbalance_dir.y() * pendulum_N_m_.y());
  }
  /// The modes' share of the spin's acceleration A (xi'' += A h_xi) or of
  /// its jump at an impact (xi' += dw h_xi), added to modal_rows (n).
  template <class Out>
  void add_spin_share(const Vec2& unbalance_dir, double amount, const Eigen::MatrixBase<Out>& modal_rows) const {
    const int n = modal_size();
    Reduced h(n + 2);
    lever(unbalance_dir, h);
    const_cast<Eigen::MatrixBase<Out>&>(modal_rows) += amount * h.tail(n);
  }
  /// max over phi of h^T M^-1 h [kg m^2]: J_eff >= J minus this.
  double max_spin_lever_kg_m2() const;
  /// h at the unbalance's direction (n + 2 entries) [kg m]: the spin's
  /// energy terms (a balance's kinetic energy holds -w h^T q').
  Eigen::VectorXd spin_lever(const Vec2& unbalance_dir) const {
    Reduced h(modal_size() + 2);
    lever(unbalance_dir, h);
    return h;
  }

  /// The time derivatives of the same along a motion under the prescribed
  /// drive (A constant on a speed segment): with the station's velocity and
  /// acceleration and rates = [xi'; xi''], the station force's rate [N/s]
  /// (returned) and xi''' (written to xi_jerk):
  ///   d/dt (-K q - (C + w G) q' + f) = -K q' - (C + w G) q'' - A G q'
  ///     + 3 w A (a cos phi + b sin phi) + w^3 (b cos phi - a sin phi).
  template <class Modal, class Out>
  Vec2 free_load_rates(const Vec2& u_dot, const Vec2& u_acc, const Eigen::MatrixBase<Modal>& rates,
                       const Vec2& unbalance_dir, double w, double A, const Eigen::MatrixBase<Out>& xi_jerk) const {
    const int n = modal_size();
    Reduced q_dot(n + 2), q_acc(n + 2), f(n + 2);
    q_dot.head<2>() = u_dot;
    q_dot.tail(n) = rates.head(n);
    q_acc.head<2>() = u_acc;
    q_acc.tail(n) = rates.tail(n);
    const double c = unbalance_dir.x(), s = unbalance_dir.y();
    f.noalias() = -k_ * q_dot;
    f.noalias() -= c_ * q_acc;
    f.noalias() -= w * (g_ * q_acc);
    f.noalias() -= A * (g_ * q_dot);
    f += (3.0 * w * A * c - w * w * w * s) * a_ + (3.0 * w * A * s + w * w * w * c) * b_;
    const_cast<Eigen::MatrixBase<Out>&>(xi_jerk) = f.tail(n);
    return f.head<2>();
  }

 private:
  using Reduced = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxModalCoordinates + 2, 1>;
  // Adds u's force to a, b and its weight to the pendulum torque.
  void add_unbalance(const RotorUnbalance& u);
  // h = a sin phi - b cos phi at the unbalance's direction (cos, sin).
  void lever(const Vec2& unbalance_dir, Reduced& h) const {
    h.noalias() = unbalance_dir.y() * a_;
    h.noalias() -= unbalance_dir.x() * b_;
  }
  ReducedRotor rotor_;
  TruncationReport truncation_;
  double station_mass_kg_;
  double contact_radius_m_;
  int probe_node_;
  double gravity_m_per_s2_;
  std::vector<int> disk_nodes_;
  Eigen::Matrix<double, 2, Eigen::Dynamic> probe_rows_;  // the expansion's rows of the probe node's x and y
  Eigen::MatrixXd node_rows_;                            // ... of every node's x and y (2 nodes() rows)
  Eigen::MatrixXd k_;                                    // K
  Eigen::MatrixXd c_, g_;                                // C, G
  Eigen::VectorXd a_, b_;                                // the unbalances at spin angle 0 and pi/2, per unit w^2 [kg m]
  Eigen::VectorXd weight_;                               // gravity's load on q [N] (constant: no rate)
  Vec2 pendulum_N_m_ = Vec2::Zero();                     // g sum m e (cos beta, sin beta): the unbalances' weight
};

/// Throws std::invalid_argument unless modal holds a block [xi; xi'] of
/// rotor (ContactMethod::start_with_modes).
template <class Modal>
void check_modal_block(const FlexibleRotorModel& rotor, const Modal& modal) {
  if (modal.size() != 2 * rotor.modal_size()) {
    throw std::invalid_argument("start_with_modes: a modal block of " + std::to_string(modal.size()) +
                                " entries; accepted: " + std::to_string(2 * rotor.modal_size()) +
                                " ([xi; xi'] of this rotor)");
  }
}

/// The free loads of a flexible rotor's state (station_model.hpp's FreeLoads): m the
/// station (station_parameters), k the station and stator, modal its
/// [xi; xi'], d the drive (drive_at); xi'' written to modal_acc. Under a motor drive
/// without the spin's share, which the caller adds once the spin's
/// acceleration is known (FlexibleRotorModel::add_spin_share); free.spin
/// then holds the coupling.
template <class Modal, class Out>
FreeLoads flexible_free_loads(const StationModel& m, const FlexibleRotorModel& rotor, const Kinematics& k,
                              const DriveState& d, const Eigen::MatrixBase<Modal>& modal,
                              const Eigen::MatrixBase<Out>& modal_acc) {
  FreeLoads free;
  free.unbalance_dir = m.unbalance_dir(d.angle_rad);
  free.stator_N = m.stator_free_force(k);
  const double accel = m.motor() ? 0.0 : d.accel_rad_per_s2;  // a motor's enters through free.spin
  free.rotor_N = rotor.free_loads(k.rotor_pos + m.frame_shift(), k.rotor_vel, modal, free.unbalance_dir,
                                  d.speed_rad_per_s, accel, modal_acc);
  if (m.motor())
    free.spin = rotor.spin_coupling(free.unbalance_dir, modal_acc, m.parameters().rotor_polar_inertia_kg_m2);
  return free;
}

/// A flexible rotor's sample s under the prescribed drive: the drive torque
/// reported for the station (m's, J A - R_r F_t) less the rotor's
/// lateral torque on the spin (lateral_torque_N_m), from s's station, drive
/// and contact force and its modal block [xi; xi'], dir the unbalances'
/// direction at s's spin angle (StationModel::unbalance_dir). A motor's
/// torque is the motor's own: s is left as it is.
template <class Modal>
void add_lateral_torque(const StationModel& m, const FlexibleRotorModel& rotor, const Eigen::MatrixBase<Modal>& modal,
                        const Vec2& dir, Sample& s) {
  if (m.motor()) return;
  ModalVector xi_acc(rotor.modal_size());
  const Vec2 station_N = rotor.free_loads(s.kin.rotor_pos, s.kin.rotor_vel, modal, dir, s.drive.speed_rad_per_s,
                                          s.drive.accel_rad_per_s2, xi_acc);
  s.drive_torque_N_m -=
      rotor.lateral_torque_N_m(dir, (station_N + s.contact_force_on_rotor_N) / rotor.station_mass_kg(), xi_acc);
}

/// Reads settings.file (rotor_file.hpp) and reduces it at its rub station to
/// settings.planar_modes per plane (0: auto, the fewest from 1 up whose
/// unbalance response is within settings.truncation_tolerance of the full
/// model's over the speeds), with the file's unbalances and gravity along -y
/// (the scene's gravity_m_per_s2), and judges the reduction's truncation
/// error on 24 speeds evenly from min_speed to max_speed (above 0) and, on a
/// run-up at acceleration_rad_per_s2, the flanks of the full model's critical
/// speeds between them (TruncationReport). Throws std::invalid_argument naming the file and what
/// is wrong (an unreadable file, a bad item, no rub_station, a count out of
/// range, auto without unbalances or speeds to judge by, or with no model
/// within the tolerance).
FlexibleRotorModel load_flexible_rotor(const RotorSettings& settings, double gravity_m_per_s2 = 0.0,
                                       double min_speed_rad_per_s = 0.0, double max_speed_rad_per_s = 0.0,
                                       double acceleration_rad_per_s2 = 0.0);

/// A rotor file read and reduced once, with the settings it was read for.
struct LoadedFlexibleRotor {
  std::string file;
  long planar_modes = 0;  ///< as asked (0: auto; the model's rotor() has the count)
  double truncation_tolerance = 0.0;
  double min_speed_rad_per_s = 0.0, max_speed_rad_per_s = 0.0, acceleration_rad_per_s2 = 0.0;
  long probe_node = 0;
  double gravity_m_per_s2 = 0.0;
  std::shared_ptr<const FlexibleRotorModel> model;
};

/// A scene's flexible rotor: the one it carries (RotorSettings::loaded) when
/// that was read for its file, planar modes, probe node and gravity, else
/// the file read now (load_flexible_rotor's errors). A run reads its rotor
/// file once (test_flexible_rotor_model, TheSceneCarriesItsRotor).
std::shared_ptr<const FlexibleRotorModel> flexible_rotor_of(const Scene& scene);
/// Sets scene.rotor.loaded to flexible_rotor_of(scene) (nothing for the Jeffcott).
void load_rotor(Scene& scene);

/// The station's parameters of a flexible rotor (StationModel, model.hpp):
/// a point of mass m_st (rotor_mass_kg), every other force on it the
/// flexible model's (FlexibleRotor, rotor_model.hpp: the station's share of
/// the weight included); the contact radius the rub station's
/// (rotor_radius_m) where the file gives one. The rest is the scene's (the
/// stator's weight among it); the Jeffcott's shaft keys are not read.
ModelParameters station_parameters(const ModelParameters& scene, const FlexibleRotorModel& rotor);

/// The radius the rotor slides at in a scene [m]: a flexible rotor's rub
/// station's contact_radius_m where its file gives one, else the scene's
/// rotor_radius_m (as station_parameters).
double contact_radius_of(const Scene& scene);

}  // namespace rotor_rub::core
