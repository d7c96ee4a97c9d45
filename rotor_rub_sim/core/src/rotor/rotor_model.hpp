/// @file
/// The seam between a rotor and the contact methods: what a method knows of
/// the rotor it runs. The contact acts at one point, the rub station, a point
/// of mass m_r on which the stator presses (station_model.hpp's StationModel: masses,
/// stator, geometry, compliance, impulses, drive); a rotor model adds every
/// other force on the station and any coordinates of its own that no contact
/// force reaches (a modal block, carried after the layout's fixed part:
/// state_layout.hpp's FreeLayout). The methods are templates on the rotor model and
/// call only what follows, so a rotor model that lacks a member does not
/// compile (docs/architecture.md, "Adding a rotor model").
///
/// A rotor model R provides:
///   State<kFixed>          a layout's state type (kFixed entries and the block)
///   ModalVector            its xi'' / xi''' storage (no allocation)
///   kStationOnly           the state is the station's and the stator's alone
///                          (no block)
///   R(scene)               the scene's rotor, read once (Scene::rotor.loaded)
///   adopt(p)               takes the scene's parameters p (at the start, at a
///                          live change) and gives the station's (StationModel)
///   modal_size()           n: xi's entries (0: no block)
///   check_block(modal)     a given start's block (start_with_modes)
///   replace(model)         a new model of the same basis (a blade loss)
///   flexible()             the flexible model, or nullptr
///   loads(m, k, d, modal, modal_acc)           every free load (FreeLoads),
///       xi'' to modal_acc; under a motor without the spin's share
///   station_force(m, k, d, dir, modal, modal_acc)   the same, prescribed drive
///   station_force_rate(m, k, acc, d, dir, rates, modal_jerk)  its time rate
///   add_spin_share(dir, amount, rows)          a motor's spin acceleration or
///       jump into the block's rates
///   add_free_jacobian<L>(m, x, d, jac, dfdt)  the free loads' partial
///       derivatives under the prescribed drive into the rows of the
///       station's acceleration and the block's xi'' of a layout L's
///       Jacobian, their partial time rate into dfdt (the penalty method's
///       closed-form Jacobian, penalty_system.hpp)
///   finish_sample(m, modal, dir, s)            the probes, and the drive
///       torque's share of the rotor's lateral motion (prescribed drive);
///       dir the unbalance's direction at s's spin angle, which a contact
///       sample's free loads hold already
#pragma once

#include <Eigen/Core>
#include <memory>
#include <stdexcept>
#include <type_traits>

#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/model.hpp"
#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

/// The paper's Jeffcott rotor: the station is the disk, held by the shaft's
/// spring and damper and driven by its unbalance (model.hpp's JeffcottModel);
/// no block.
class JeffcottRotor {
 public:
  template <int kFixed>
  using State = Eigen::Matrix<double, kFixed, 1>;
  using ModalVector = Eigen::Matrix<double, 0, 1>;
  static constexpr bool kStationOnly = true;

  explicit JeffcottRotor(const ModelParameters& p) : jeffcott_(p) {}
  explicit JeffcottRotor(const Scene& scene) : jeffcott_(scene.model) {}
  ModelParameters adopt(const ModelParameters& scene) {
    jeffcott_ = JeffcottModel(scene);
    return scene;
  }
  int modal_size() const { return 0; }
  void check_block(const ModalState& /*modal*/) const {
    throw std::logic_error("start_with_modes: this method runs the Jeffcott rotor");
  }
  void replace(std::shared_ptr<const FlexibleRotorModel> /*model*/) {
    throw std::logic_error("change_rotor: this method runs the Jeffcott rotor");
  }
  const FlexibleRotorModel* flexible() const { return nullptr; }

  template <class Modal, class Out>
  FreeLoads loads(const StationModel& /*m*/, const Kinematics& k, const DriveState& d,
                  const Eigen::MatrixBase<Modal>& /*modal*/, const Eigen::MatrixBase<Out>& /*modal_acc*/) const {
    return jeffcott_.free_loads(k, d);
  }
  template <class Modal, class Out>
  Vec2 station_force(const StationModel& /*m*/, const Kinematics& k, const DriveState& d, const Vec2& unbalance_dir,
                     const Eigen::MatrixBase<Modal>& /*modal*/, const Eigen::MatrixBase<Out>& /*modal_acc*/) const {
    return jeffcott_.rotor_free_force(k, d, unbalance_dir);
  }
  template <class Rates, class Out>
  Vec2 station_force_rate(const StationModel& /*m*/, const Kinematics& k, const Vec2& station_acc, const DriveState& d,
                          const Vec2& unbalance_dir, const Eigen::MatrixBase<Rates>& /*rates*/,
                          const Eigen::MatrixBase<Out>& /*modal_jerk*/) const {
    return jeffcott_.rotor_free_force_derivative(k, station_acc, d, unbalance_dir);
  }
  template <class Out>
  void add_spin_share(const Vec2& /*unbalance_dir*/, double /*amount*/,
                      const Eigen::MatrixBase<Out>& /*modal_rows*/) const {}
  /// The shaft's spring and damper on the station, the unbalance's rate.
  template <class L, class State, class Matrix>
  void add_free_jacobian(const StationModel& m, const State& /*x*/, const DriveState& d, Matrix& jac,
                         State& dfdt) const {
    const JeffcottModel::FreeForceGains gains = jeffcott_.free_force_gains();
    const double imr = m.inv_rotor_mass();
    jac.template block<2, 2>(L::kRotorVel, L::kRotorPos).diagonal().array() -= gains.rotor_stiffness_N_per_m * imr;
    jac.template block<2, 2>(L::kRotorVel, L::kRotorVel).diagonal().array() -= gains.rotor_damping_N_s_per_m * imr;
    dfdt.template segment<2>(L::kRotorVel) += jeffcott_.rotor_free_force_rate(d) * imr;
  }
  /// Under the prescribed drive the torque takes the unbalance's lever in,
  /// - e F . u (JeffcottModel::unbalance_torque_N_m).
  template <class Modal>
  void finish_sample(const StationModel& m, const Eigen::MatrixBase<Modal>& /*modal*/, const Vec2& unbalance_dir,
                     Sample& s) const {
    if (m.motor()) return;
    s.drive_torque_N_m -= jeffcott_.unbalance_torque_N_m(s.kin, unbalance_dir, s.contact_force_on_rotor_N);
  }

 private:
  JeffcottModel jeffcott_;
};

/// A flexible rotor reduced to its rub station and a modal block
/// (flexible_rotor_model.hpp): the station a point of mass m_st
/// (station_parameters), every other force on it the reduced model's, the
/// block's rows xi'' untouched by any contact force or impulse but for a
/// motor's spin, whose acceleration and jumps it shares.
class FlexibleRotor {
 public:
  template <int kFixed>
  using State = FlexibleState;
  using ModalVector = core::ModalVector;
  static constexpr bool kStationOnly = false;

  explicit FlexibleRotor(const Scene& scene) : model_(flexible_rotor_of(scene)) {}
  ModelParameters adopt(const ModelParameters& scene) const { return station_parameters(scene, *model_); }
  int modal_size() const { return model_->modal_size(); }
  void check_block(const ModalState& modal) const { check_modal_block(*model_, modal); }
  void replace(std::shared_ptr<const FlexibleRotorModel> model) { model_ = std::move(model); }
  const FlexibleRotorModel* flexible() const { return model_.get(); }

  template <class Modal, class Out>
  FreeLoads loads(const StationModel& m, const Kinematics& k, const DriveState& d,
                  const Eigen::MatrixBase<Modal>& modal, const Eigen::MatrixBase<Out>& modal_acc) const {
    return flexible_free_loads(m, *model_, k, d, modal, modal_acc);
  }
  template <class Modal, class Out>
  Vec2 station_force(const StationModel& m, const Kinematics& k, const DriveState& d, const Vec2& unbalance_dir,
                     const Eigen::MatrixBase<Modal>& modal, const Eigen::MatrixBase<Out>& modal_acc) const {
    return model_->free_loads(k.rotor_pos + m.frame_shift(), k.rotor_vel, modal, unbalance_dir, d.speed_rad_per_s,
                              d.accel_rad_per_s2, modal_acc);
  }
  template <class Rates, class Out>
  Vec2 station_force_rate(const StationModel& /*m*/, const Kinematics& k, const Vec2& station_acc, const DriveState& d,
                          const Vec2& unbalance_dir, const Eigen::MatrixBase<Rates>& rates,
                          const Eigen::MatrixBase<Out>& modal_jerk) const {
    return model_->free_load_rates(k.rotor_vel, station_acc, rates, unbalance_dir, d.speed_rad_per_s,
                                   d.accel_rad_per_s2, modal_jerk);
  }
  template <class Out>
  void add_spin_share(const Vec2& unbalance_dir, double amount, const Eigen::MatrixBase<Out>& modal_rows) const {
    model_->add_spin_share(unbalance_dir, amount, modal_rows);
  }
  /// -K by q = [u; xi] and -(C + w G) by q' in the rows of u'' (over m_st)
  /// and xi'', the unbalances' and w G's rate (free_load_time_rate: the
  /// block's rows of dfdt written, which no other load reaches).
  template <class L, class State, class Matrix>
  void add_free_jacobian(const StationModel& m, const State& x, const DriveState& d, Matrix& jac, State& dfdt) const {
    const int n = model_->modal_size();
    const Eigen::MatrixXd &k = model_->stiffness_matrix(), &c = model_->damping_matrix(),
                          &g = model_->gyroscopic_matrix();
    const double w = d.speed_rad_per_s;
    // q = [u; xi] in the layout: its positions' and velocities' first rows,
    // each part's size and its first row in q; the station's rows over m_st.
    const int pos[2] = {L::kRotorPos, L::kModal}, vel[2] = {L::kRotorVel, L::kModal + n};
    const int size[2] = {2, n}, first[2] = {0, 2};
    const double scale[2] = {m.inv_rotor_mass(), 1.0};
    for (int r = 0; r < 2; ++r) {
      for (int col = 0; col < 2; ++col) {
        jac.block(vel[r], pos[col], size[r], size[col]) -= scale[r] * k.block(first[r], first[col], size[r], size[col]);
        jac.block(vel[r], vel[col], size[r], size[col]) -=
            scale[r] *
            (c.block(first[r], first[col], size[r], size[col]) + w * g.block(first[r], first[col], size[r], size[col]));
      }
    }
    const Vec2 station_rate =
        model_->free_load_time_rate(x.template segment<2>(L::kRotorVel), x.tail(2 * n), m.unbalance_dir(d.angle_rad), w,
                                    d.accel_rad_per_s2, dfdt.segment(L::kModal + n, n));
    dfdt.template segment<2>(L::kRotorVel) += station_rate * scale[0];
  }
  /// The probes read their node; under the prescribed drive the torque takes
  /// the lateral motion's in (add_lateral_torque).
  template <class Modal>
  void finish_sample(const StationModel& m, const Eigen::MatrixBase<Modal>& modal, const Vec2& unbalance_dir,
                     Sample& s) const {
    s.probe_displacement_m = model_->probe_displacement(s.kin.rotor_pos, modal);
    add_lateral_torque(m, *model_, modal, unbalance_dir, s);
  }

 private:
  std::shared_ptr<const FlexibleRotorModel> model_;
};

/// The free loads of a state x of layout L for its derivative dxdt: the
/// block's position rows xi' copied from x, its rate rows xi'' written by the
/// rotor (a motor's spin share still to add: add_spin_share), dxdt sized.
template <class L, class Rotor>
FreeLoads derivative_loads(const Rotor& rotor, const StationModel& m, const Kinematics& k, const DriveState& d,
                           const typename L::State& x, typename L::State& dxdt) {
  const int n = modal_count<L>(x);
  dxdt.resize(x.size());
  dxdt.segment(L::kModal, n) = x.tail(n);
  return rotor.loads(m, k, d, x.tail(2 * n), dxdt.tail(n));
}

/// The free system's Jacobian at x of layout L ([q, v] then a block's xi and
/// xi') under the prescribed drive d: the positions' rows [0 I], the rotor's
/// free loads (add_free_jacobian) and an elastic stator's spring and damper;
/// their partial time rate into dfdt. Free flight's whole Jacobian (the
/// switching and iteration methods' free integrator), the part of the penalty
/// method's that the contact law adds to (test_penalty_jacobian.cpp).
template <class L, class Rotor, class Matrix>
void free_jacobian(const Rotor& rotor, const StationModel& m, const typename L::State& x, const DriveState& d,
                   Matrix& jac, typename L::State& dfdt) {
  static_assert(L::kRotorVel == L::kDof && L::kSize == 2 * L::kDof, "[q, v] layout (no spin)");
  const int n = modal_count<L>(x);
  jac.setZero(x.size(), x.size());
  dfdt.setZero(x.size());
  jac.template block<2, 2>(L::kRotorPos, L::kRotorVel).setIdentity();
  for (int i = 0; i < n; ++i) jac(L::kModal + i, L::kModal + n + i) = 1.0;
  rotor.template add_free_jacobian<L>(m, x, d, jac, dfdt);
  if constexpr (L::kDof == 4) {  // an elastic stator
    const double ims = m.inv_stator_mass();
    const ModelParameters& p = m.parameters();
    const Eigen::Matrix2d eye = Eigen::Matrix2d::Identity();
    jac.template block<2, 2>(L::kStatorPos, L::kStatorVel) = eye;
    jac.template block<2, 2>(L::kStatorVel, L::kStatorPos) = -p.stator_stiffness_N_per_m * ims * eye;
    jac.template block<2, 2>(L::kStatorVel, L::kStatorVel) = -p.stator_damping_N_s_per_m * ims * eye;
  }
}

/// The stiff integrator's hooks (dense_rodasp.hpp) of a system whose
/// Jacobian is free flight's (free_jacobian): in closed form under the
/// prescribed drive, the positions' rows [0 I] (the second-order solve,
/// kFixedDof the positions before a block); under a motor the spin couples
/// every row and the integrator differences. The switching and iteration
/// methods' free flight derive from it.
template <class L, bool kMotor>
struct FreeFlightJacobianHooks {
  static constexpr bool kAnalyticJacobian = !kMotor;
  static constexpr bool kSecondOrderJacobian = kAnalyticJacobian;
  static constexpr int kFixedDof = L::kDof;
  static constexpr bool kOwnErrorNorm = false;
  using Matrix =
      std::conditional_t<kHasModalBlock<typename L::State>, Eigen::MatrixXd, Eigen::Matrix<double, L::kSize, L::kSize>>;
};

/// The free loads of a state given as its kinematics k and block modal (an
/// impact's, a sample's), xi'' discarded.
template <class Rotor>
FreeLoads loads_at(const Rotor& rotor, const StationModel& m, const Kinematics& k, const DriveState& d,
                   const ModalState& modal) {
  typename Rotor::ModalVector modal_acc(rotor.modal_size());
  return rotor.loads(m, k, d, modal, modal_acc);
}

}  // namespace rotor_rub::core
