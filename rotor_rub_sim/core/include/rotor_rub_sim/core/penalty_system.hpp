// The penalty method's right-hand side (penalty_method.cpp), in a header of
// its own so that its closed-form Jacobian can be tested against differences
// (test_penalty_jacobian.cpp).
#pragma once

#include <Eigen/Dense>

#include "rotor_rub_sim/core/cost_profiler.hpp"
#include "rotor_rub_sim/core/model.hpp"
#include "rotor_rub_sim/core/penalty_law.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"

namespace rotor_rub::core {

// kModeLocked: the field of one mode (penalty_law.hpp), for the implicit
// integrator, whose steps the kinks would otherwise cut down; else the
// clamped law itself, for the explicit ones, whose steps the contact's
// stiffness bounds far below any kink's effect (dopri5 took the same steps to
// the digit either way at rtol 1e-3, 1e-5 and 1e-7 on the paper scene), and
// which at loose tolerances hop across the edges every few steps (at rtol
// 1e-3 the position error allowed is about 400 times the penetration, 3e-6 m
// against 8e-9 m): the clamp absorbs that noise where restarts would
// multiply it (182k restarts and 2.8 times the time, measured).
template <int kStatorDof, bool kMotor, bool kModeLocked>
struct PenaltySystem {
  using L = FreeLayout<kStatorDof, kMotor>;
  using State = typename L::State;
  const JeffcottModel* model = nullptr;
  PenaltyLaw law;
  PenaltyMode mode;  // the smooth piece being integrated (penalty_law.hpp)
  SpeedSegment segment;
  double* rhs_time_s = nullptr;  // profiling only

  void operator()(const State& x, State& dxdt, double t) const {
    ProfileScope scope(rhs_time_s);
    const Kinematics k = kinematics_of<kStatorDof, kMotor>(x);
    const DriveState reference = segment.at(t);
    const DriveState d = model->drive_at(k, reference);
    const ContactGeometry g = model->contact_geometry(k, d);
    double fn, ft;
    if constexpr (kModeLocked) {
      if (mode.clamped) {
        fn = law.normal(g);
        ft = law.tangential(g, fn);
      } else {
        fn = law.normal(g, mode);
        ft = law.tangential(g, fn, mode);
      }
    } else {
      fn = law.normal(g);
      ft = law.tangential(g, fn);
    }
    const Accelerations a = model->accelerations(k, d, g, fn, ft);
    dxdt.template segment<2>(L::kRotorPos) = k.rotor_vel;
    dxdt.template segment<2>(L::kRotorVel) = a.rotor;
    if constexpr (kStatorDof == 2) {
      dxdt.template segment<2>(L::kStatorPos) = k.stator_vel;
      dxdt.template segment<2>(L::kStatorVel) = a.stator;
    }
    spin_derivative<L>(*model, k, reference, a.spin_rad_per_s2, dxdt);
  }
  // The Jacobian df/dx and the partial df/dt in closed form (the integrator
  // would otherwise take kSize + 2 derivatives a step for them: 10 of
  // RODASP's 16 on the paper scene). Of the mode's law (of the clamped law's
  // piece at x on a fallback step); under a motor drive the spin couples
  // every row, and the integrator differences instead (kAnalyticJacobian).
  static constexpr bool kAnalyticJacobian = !kMotor;
  // Positions then velocities, nothing else (FreeLayout without the spin).
  static constexpr bool kSecondOrderJacobian = !kMotor;
  static_assert(kMotor || (L::kRotorVel == L::kDof && L::kSize == 2 * L::kDof), "[q, v] layout");
  using Matrix = Eigen::Matrix<double, L::kSize, L::kSize>;
  void jacobian(const State& x, double t, Matrix& jac, State& dfdt) const {
    static_assert(!kMotor, "the motor drive's Jacobian is differenced");
    const Kinematics k = kinematics_of<kStatorDof, kMotor>(x);
    const DriveState d = segment.at(t);
    const ContactGeometry g = model->contact_geometry(k, d);
    const PenaltyMode m = !kModeLocked || mode.clamped ? law.mode_of(law.edges(g)) : mode;
    const double radius_m = model->parameters().rotor_radius_m;
    const auto c = law.force_jacobian(g, k.rotor_vel - k.stator_vel, m, d.accel_rad_per_s2 * radius_m);
    const JeffcottModel::FreeForceGains free = model->free_force_gains();
    const double imr = model->inv_rotor_mass();
    const Eigen::Matrix2d eye = Eigen::Matrix2d::Identity();
    jac.setZero();
    dfdt.setZero();
    jac.template block<2, 2>(L::kRotorPos, L::kRotorVel) = eye;
    jac.template block<2, 2>(L::kRotorVel, L::kRotorPos) = (c.d_rel_pos - free.rotor_stiffness_N_per_m * eye) * imr;
    jac.template block<2, 2>(L::kRotorVel, L::kRotorVel) = (c.d_rel_vel - free.rotor_damping_N_s_per_m * eye) * imr;
    dfdt.template segment<2>(L::kRotorVel) = (model->rotor_free_force_rate(d) + c.d_time) * imr;
    if constexpr (kStatorDof == 2) {
      // The stator takes -F_c, a function of rel = r_r - r_s.
      const double ims = model->inv_stator_mass();
      jac.template block<2, 2>(L::kStatorPos, L::kStatorVel) = eye;
      jac.template block<2, 2>(L::kRotorVel, L::kStatorPos) = -c.d_rel_pos * imr;
      jac.template block<2, 2>(L::kRotorVel, L::kStatorVel) = -c.d_rel_vel * imr;
      jac.template block<2, 2>(L::kStatorVel, L::kRotorPos) = -c.d_rel_pos * ims;
      jac.template block<2, 2>(L::kStatorVel, L::kRotorVel) = -c.d_rel_vel * ims;
      jac.template block<2, 2>(L::kStatorVel, L::kStatorPos) =
          (c.d_rel_pos - free.stator_stiffness_N_per_m * eye) * ims;
      jac.template block<2, 2>(L::kStatorVel, L::kStatorVel) =
          (c.d_rel_vel - free.stator_damping_N_s_per_m * eye) * ims;
      dfdt.template segment<2>(L::kStatorVel) = -c.d_time * ims;
    }
  }
};

}  // namespace rotor_rub::core
