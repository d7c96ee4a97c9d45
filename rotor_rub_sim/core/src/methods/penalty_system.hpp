// The penalty method's right-hand side (penalty_method_impl.hpp), in a header of
// its own so that its closed-form Jacobian can be tested against differences
// (test_penalty_jacobian.cpp).
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <type_traits>

#include "contact/penalty_law.hpp"
#include "rotor/rotor_model.hpp"
#include "rotor_rub_sim/core/model.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"
#include "run/cost_profiler.hpp"

namespace rotor_rub::core {

// kModeLocked: the field of one mode (penalty_law.hpp), for the implicit
// integrator, whose steps the kinks would otherwise cut down. Else, for the
// explicit ones, no contact force out of contact and the clamped law in
// it: the touchdown, where the damper's force jumps by c_c delta', is
// located and restarted at (an explicit step across that jump has an error
// that does not shrink with the step, and the controller stalls on it at
// tight tolerances); the kinks inside a contact are left to the clamp, since
// the contact's stiffness bounds the steps far below any kink's effect and
// at loose tolerances the steps hop across those edges every few steps (at
// rtol 1e-3 the position error allowed is about 400 times the penetration,
// 3e-6 m against 8e-9 m): restarts there would multiply that noise.
// Rotor: the rotor model (rotor_model.hpp), whose free loads and block's rows
// the station's take; the law acts on the station alone.
template <int kStatorDof, bool kMotor, bool kModeLocked, class Rotor = JeffcottRotor>
struct PenaltySystem {
  using L = FreeLayout<kStatorDof, kMotor, Rotor>;
  using State = typename L::State;
  const StationModel* model = nullptr;
  const Rotor* rotor = nullptr;
  PenaltyLaw law;
  PenaltyMode mode;  // the smooth piece being integrated (penalty_law.hpp)
  SpeedSegment segment;
  double* rhs_time_s = nullptr;  // profiling only

  // The accelerations under the law (the mode's, or the clamped law) at the
  // drive d of drive_at() and the contact's geometry g, from the state's
  // free loads (the rotor model's) [m/s^2, rad/s^2].
  Accelerations accelerations(const DriveState& d, const ContactGeometry& g, const FreeLoads& free) const {
    double fn, ft;
    if constexpr (kModeLocked) {
      if (mode.clamped) {
        fn = law.normal(g);
        ft = law.tangential(g, fn);
      } else {
        fn = law.normal(g, mode);
        ft = law.tangential(g, fn, mode);
      }
    } else if (mode.pressed || mode.clamped) {
      fn = law.normal(g);
      ft = law.tangential(g, fn);
    } else {
      fn = ft = 0.0;
    }
    return model->accelerations(d, g, free, fn, ft);
  }

  void operator()(const State& x, State& dxdt, double t) const {
    ProfileScope scope(rhs_time_s);
    const Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
    const DriveState reference = segment.at(t);
    const DriveState d = model->drive_at(k, reference);
    const FreeLoads free = derivative_loads<L>(*rotor, *model, k, d, x, dxdt);
    const Accelerations a = accelerations(d, model->contact_geometry(k, d), free);
    // A motor's spin: the rotor's block takes its share of its acceleration.
    if constexpr (kMotor) rotor->add_spin_share(free.unbalance_dir, a.spin_rad_per_s2, dxdt.tail(modal_count<L>(x)));
    free_derivative<L>(*model, k, reference, a, dxdt);
  }
  // The Jacobian df/dx and the partial df/dt in closed form (the integrator
  // would otherwise take kSize + 2 derivatives a step for them: 10 of
  // RODASP's 16 on the paper scene, 34 on the seal rotor's 8 planar modes).
  // Of the mode's law (of the clamped law's piece at x on a fallback step);
  // the rotor's own loads are its model's (add_free_jacobian). Under a motor
  // drive the spin couples every row, and the integrator differences
  // instead (kAnalyticJacobian).
  static constexpr bool kAnalyticJacobian = !kMotor;
  // Positions then velocities (FreeLayout without the spin), then a block's
  // xi and xi': the rows of the positions are [0 I] (dense_rodasp.hpp's
  // second-order solve, kFixedDof the positions before the block).
  static constexpr bool kSecondOrderJacobian = kAnalyticJacobian;
  static constexpr int kFixedDof = L::kDof;
  static constexpr bool kOwnErrorNorm = false;  // the Cartesian state is the user's
  static_assert(kMotor || (L::kRotorVel == L::kDof && L::kSize == 2 * L::kDof), "[q, v] layout");
  using Matrix = std::conditional_t<kHasModalBlock<State>, Eigen::MatrixXd, Eigen::Matrix<double, L::kSize, L::kSize>>;
  void jacobian(const State& x, double t, Matrix& jac, State& dfdt) const {
    static_assert(kAnalyticJacobian, "the motor drive's Jacobian is differenced");
    static_assert(kModeLocked, "the explicit integrators take no Jacobian");
    const Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
    const DriveState d = segment.at(t);
    const ContactGeometry g = model->contact_geometry(k, d);
    const PenaltyMode m = mode.clamped ? law.mode_of(law.edges(g)) : mode;
    const double radius_m = model->parameters().rotor_radius_m;
    const auto c = law.force_jacobian(g, k.rotor_vel - k.stator_vel, m, d.accel_rad_per_s2 * radius_m);
    const double imr = model->inv_rotor_mass();
    free_jacobian<L>(*rotor, *model, x, d, jac, dfdt);
    jac.template block<2, 2>(L::kRotorVel, L::kRotorPos) += c.d_rel_pos * imr;
    jac.template block<2, 2>(L::kRotorVel, L::kRotorVel) += c.d_rel_vel * imr;
    dfdt.template segment<2>(L::kRotorVel) += c.d_time * imr;
    if constexpr (kStatorDof == 2) {
      // The stator takes -F_c, a function of rel = r_r - r_s (its own spring
      // and damper are free_jacobian's).
      const double ims = model->inv_stator_mass();
      jac.template block<2, 2>(L::kRotorVel, L::kStatorPos) = -c.d_rel_pos * imr;
      jac.template block<2, 2>(L::kRotorVel, L::kStatorVel) = -c.d_rel_vel * imr;
      jac.template block<2, 2>(L::kStatorVel, L::kRotorPos) = -c.d_rel_pos * ims;
      jac.template block<2, 2>(L::kStatorVel, L::kRotorVel) = -c.d_rel_vel * ims;
      jac.template block<2, 2>(L::kStatorVel, L::kStatorPos) += c.d_rel_pos * ims;
      jac.template block<2, 2>(L::kStatorVel, L::kStatorVel) += c.d_rel_vel * ims;
      dfdt.template segment<2>(L::kStatorVel) -= c.d_time * ims;
    }
  }
};

// The pressed mode in the contact's polar coordinates, for the implicit
// integrator: the rotor relative to the stator at distance delta and angle
// psi, r_r = r_s + delta n(psi), n = (cos psi, sin psi), t = (-sin, cos):
//   delta'' = n . (a_r - a_s) + delta psi'^2,
//   psi''   = (t . (a_r - a_s) - 2 delta' psi') / delta,
// the accelerations the same model and law give (PenaltySystem); a rotor's
// block [xi; xi'] follows as in the Cartesian state (FreeLayout), untouched.
// Why: the contact's stiffness k_c acts along n, which turns with the whirl.
// In Cartesian coordinates the stiff direction of the Jacobian turns by w h
// within a step, and a Rosenbrock method, which holds the Jacobian of the
// step's start, loses accuracy on it: on the paper scene RODASP kept steps
// of ~4.5e-5 s in sustained contact at rtol 3e-5, where a contact that does
// not turn (a rotor pressed down by gravity) took ~4.5e-4 s (measured;
// test SustainedRubStepsInPolarCoordinates). In these coordinates the stiff
// direction is delta's, fixed. Free flight and the clamped law's fallback
// steps stay Cartesian (delta = 0, the rotor centred, has no angle; a
// fallback step may leave the contact).
template <int kStatorDof, bool kMotor, class Rotor = JeffcottRotor>
struct PolarLayout : SpinLayout<kMotor, 2 * (2 + kStatorDof)> {
  static constexpr int kDof = 2 + kStatorDof;
  static constexpr int kSize = 2 * kDof + SpinLayout<kMotor, 0>::kSpinSize;  // the fixed part
  static constexpr int kStatorPos = 0;                                       // x_s, y_s [m] (elastic only)
  static constexpr int kDistance = kStatorDof;                               // delta = |r_r - r_s| [m]
  static constexpr int kAngle = kStatorDof + 1;                              // psi [rad]
  static constexpr int kStatorVel = kDof;                                    // x_s', y_s' [m/s] (elastic only)
  static constexpr int kDistanceRate = kDof + kStatorDof;                    // delta' [m/s]
  static constexpr int kAngleRate = kDistanceRate + 1;                       // psi' [rad/s]
  static constexpr int kModal = kSize;                                       // the rotor's block, as FreeLayout's
  using State = typename Rotor::template State<kSize>;
};

template <int kStatorDof, bool kMotor, bool kModeLocked = true, class Rotor = JeffcottRotor>
struct PenaltyPolarSystem {
  using L = PolarLayout<kStatorDof, kMotor, Rotor>;
  using FL = FreeLayout<kStatorDof, kMotor, Rotor>;
  using Cartesian = PenaltySystem<kStatorDof, kMotor, kModeLocked, Rotor>;
  using State = typename L::State;
  static_assert(L::kSize == FL::kSize && std::is_same_v<State, typename FL::State>, "the same integrator takes both");
  const Cartesian* cartesian = nullptr;  // model, rotor, law, mode, drive

  static Kinematics kinematics(const State& x) {
    const double psi = x[L::kAngle];
    const Vec2 n(std::cos(psi), std::sin(psi));
    return kinematics(x, n, Vec2(-n.y(), n.x()));
  }
  // The same, given n and t of the state's psi.
  static Kinematics kinematics(const State& x, const Vec2& n, const Vec2& t) {
    Kinematics k;
    const double delta = x[L::kDistance];
    if constexpr (kStatorDof == 2) {
      k.stator_pos = x.template segment<2>(L::kStatorPos);
      k.stator_vel = x.template segment<2>(L::kStatorVel);
    }
    k.rotor_pos = k.stator_pos + delta * n;
    k.rotor_vel = k.stator_vel + x[L::kDistanceRate] * n + (delta * x[L::kAngleRate]) * t;
    read_spin<L>(x, k.spin);
    return k;
  }

  // The polar state of kinematics k, delta > 0 (a pressed contact has delta
  // > C, or a rounding below it at a crossed edge), written to x's fixed
  // part (x sized: sized_state(), its block set).
  static void store(const Kinematics& k, State& x) {
    const Vec2 rel = k.rotor_pos - k.stator_pos, rel_vel = k.rotor_vel - k.stator_vel;
    const double delta = rel.norm();
    const Vec2 n = rel / delta, t(-n.y(), n.x());
    if constexpr (kStatorDof == 2) {
      x.template segment<2>(L::kStatorPos) = k.stator_pos;
      x.template segment<2>(L::kStatorVel) = k.stator_vel;
    }
    x[L::kDistance] = delta;
    x[L::kAngle] = std::atan2(rel.y(), rel.x());
    x[L::kDistanceRate] = rel_vel.dot(n);
    x[L::kAngleRate] = rel_vel.dot(t) / delta;
    write_spin<L>(k.spin, x);
  }
  // The same for a rotor without a block.
  static State reduce(const Kinematics& k) {
    State x;
    store(k, x);
    return x;
  }

  // The Jacobian and df/dt in closed form: the Cartesian ones
  // (PenaltySystem::jacobian) at the Cartesian state y of x, by the chain
  // rule through y(x) and the polar rows above, g = a_r - a_s:
  //   d(delta'') = n . dg + (g . t) dpsi + psi'^2 ddelta + 2 delta psi' dpsi',
  //   d(psi'')   = (t . dg - (g . n) dpsi - 2 psi' ddelta' - 2 delta' dpsi'
  //                 - psi'' ddelta) / delta,
  // with dr_r = dr_s + n ddelta + delta t dpsi and dv_r = dv_s + n ddelta'
  // + delta t dpsi' + psi' t ddelta + (delta' t - delta psi' n) dpsi; the
  // block's rows are the Cartesian ones through the same map. Second order
  // as the Cartesian one ([0 I; A B], the block's xi then xi').
  static constexpr bool kAnalyticJacobian = !kMotor;
  static constexpr bool kSecondOrderJacobian = !kMotor;
  static constexpr int kFixedDof = L::kDof;
  static constexpr bool kOwnErrorNorm = true;  // error_norm() below
  using Matrix = typename Cartesian::Matrix;
  using FixedMatrix = Eigen::Matrix<double, L::kSize, L::kSize>;
  // The Cartesian Jacobian's storage, sized before a run advances
  // (reserve(): no allocation per step).
  void reserve(Eigen::Index size) { cartesian_jac_.setZero(size, size); }
  void jacobian(const State& x, double t_s, Matrix& jac, State& dfdt) const {
    static_assert(!kMotor, "the motor drive's Jacobian is differenced");
    constexpr int kFixed = L::kSize;
    const Eigen::Index size = x.size(), block = size - kFixed, n = block / 2;
    const double delta = x[L::kDistance], psi = x[L::kAngle];
    const double delta_rate = x[L::kDistanceRate], psi_rate = x[L::kAngleRate];
    const Vec2 nrm(std::cos(psi), std::sin(psi)), t(-nrm.y(), nrm.x());
    const Kinematics k = kinematics(x, nrm, t);
    State y = x;
    store_kinematics<kStatorDof, kMotor, Rotor>(k, y);
    Matrix& cj = cartesian_jac_;
    State cart_dfdt;
    cartesian->jacobian(y, t_s, cj, cart_dfdt);
    const FixedMatrix dy = tangent_map(x, nrm, t);
    // Rows of the Cartesian Jacobian in the polar state's columns: the fixed
    // part's through dy, the block's as they are.
    using Rows = Eigen::Matrix<double, 2, Eigen::Dynamic, 0, 2, State::MaxRowsAtCompileTime>;
    auto polar_rows = [&](int first) {
      Rows r(2, size);
      r.leftCols(kFixed).noalias() = cj.template block<2, kFixed>(first, 0) * dy;
      r.rightCols(block) = cj.block(first, kFixed, 2, block);
      return r;
    };
    const Rows rotor_acc = polar_rows(FL::kRotorVel);
    Rows stator_acc = Rows::Zero(2, size);
    Vec2 stator_acc_rate = Vec2::Zero();
    if constexpr (kStatorDof == 2) {
      stator_acc = polar_rows(FL::kStatorVel);
      stator_acc_rate = cart_dfdt.template segment<2>(FL::kStatorVel);
    }
    const Rows rel_acc = rotor_acc - stator_acc;
    const Vec2 rel_acc_rate = cart_dfdt.template segment<2>(FL::kRotorVel) - stator_acc_rate;
    const DriveState d = cartesian->model->drive_at(k, cartesian->segment.at(t_s));
    const Accelerations a = accelerations(x, nrm, t, k, d);
    const Vec2 g = a.rotor - a.stator;
    const double psi_acc = (g.dot(t) - 2.0 * delta_rate * psi_rate) / delta;
    jac.setZero(size, size);
    dfdt.setZero(size);
    for (int i = 0; i < L::kDof; ++i) jac(i, L::kDof + i) = 1.0;
    jac.row(L::kDistanceRate) = nrm.transpose() * rel_acc;
    jac(L::kDistanceRate, L::kAngle) += g.dot(t);
    jac(L::kDistanceRate, L::kDistance) += psi_rate * psi_rate;
    jac(L::kDistanceRate, L::kAngleRate) += 2.0 * delta * psi_rate;
    jac.row(L::kAngleRate) = t.transpose() * rel_acc;
    jac(L::kAngleRate, L::kAngle) -= g.dot(nrm);
    jac(L::kAngleRate, L::kDistanceRate) -= 2.0 * psi_rate;
    jac(L::kAngleRate, L::kAngleRate) -= 2.0 * delta_rate;
    jac(L::kAngleRate, L::kDistance) -= psi_acc;
    jac.row(L::kAngleRate) /= delta;
    dfdt[L::kDistanceRate] = nrm.dot(rel_acc_rate);
    dfdt[L::kAngleRate] = t.dot(rel_acc_rate) / delta;
    if constexpr (kStatorDof == 2) {
      jac.template middleRows<2>(L::kStatorVel) = stator_acc;
      dfdt.template segment<2>(L::kStatorVel) = stator_acc_rate;
    }
    for (Eigen::Index i = 0; i < n; ++i) jac(L::kModal + i, L::kModal + n + i) = 1.0;
    if (n > 0) {
      jac.block(L::kModal + n, 0, n, kFixed).noalias() = cj.block(FL::kModal + n, 0, n, kFixed) * dy;
      jac.block(L::kModal + n, kFixed, n, block) = cj.block(FL::kModal + n, kFixed, n, block);
      dfdt.tail(n) = cart_dfdt.tail(n);
    }
  }

  // The contact's geometry read off the coordinates (station_model.hpp's
  // contact_geometry() finds the same from the positions, less exactly:
  // r_r - r_s = (r_s + delta n) - r_s carries eps |r| of rounding, which k_c
  // turns into ~4e-10 N of F_n).
  ContactGeometry geometry(const State& x, const Vec2& n, const Vec2& t, const DriveState& d) const {
    ContactGeometry g;
    g.distance_m = x[L::kDistance];
    g.normal = n;
    g.tangent = t;
    g.penetration_m = g.distance_m - cartesian->model->parameters().clearance_m;
    g.normal_velocity_m_per_s = x[L::kDistanceRate];
    g.sliding_velocity_m_per_s =
        g.distance_m * x[L::kAngleRate] + d.speed_rad_per_s * cartesian->model->parameters().rotor_radius_m;
    return g;
  }

  // dy/dx of the fixed part: how the Cartesian state's (FreeLayout's) moves
  // with x's at x; the block maps to itself.
  static FixedMatrix tangent_map(const State& x, const Vec2& n, const Vec2& t) {
    const double delta = x[L::kDistance], delta_rate = x[L::kDistanceRate], psi_rate = x[L::kAngleRate];
    FixedMatrix dy = FixedMatrix::Zero();
    dy.template block<2, 1>(FL::kRotorPos, L::kDistance) = n;
    dy.template block<2, 1>(FL::kRotorPos, L::kAngle) = delta * t;
    dy.template block<2, 1>(FL::kRotorVel, L::kDistanceRate) = n;
    dy.template block<2, 1>(FL::kRotorVel, L::kAngleRate) = delta * t;
    dy.template block<2, 1>(FL::kRotorVel, L::kDistance) = psi_rate * t;
    dy.template block<2, 1>(FL::kRotorVel, L::kAngle) = delta_rate * t - (delta * psi_rate) * n;
    if constexpr (kStatorDof == 2) {
      dy.template block<2, 2>(FL::kRotorPos, L::kStatorPos).setIdentity();
      dy.template block<2, 2>(FL::kStatorPos, L::kStatorPos).setIdentity();
      dy.template block<2, 2>(FL::kRotorVel, L::kStatorVel).setIdentity();
      dy.template block<2, 2>(FL::kStatorVel, L::kStatorVel).setIdentity();
    }
    if constexpr (L::kSpinSize > 0) {
      for (int i = 0; i < L::kSpinSize; ++i) dy(FL::kSpinAngle + i, L::kSpinAngle + i) = 1.0;
    }
    return dy;
  }

  // The step's error measured as the Cartesian state's (what rtol and atol
  // mean to the user, the same in every coordinates): the error vector
  // mapped by dy/dx at the step's start, each Cartesian component weighed
  // by atol + rtol max(|y0|, |y1|), the RMS norm of DenseRodasp. With the
  // polar state's own magnitudes instead, delta' (~1e-6 m/s in sustained
  // contact against the rotor's ~0.5 m/s) would be held to atol alone: at
  // rtol 1e-9 / atol 1e-12 on the paper scene 131k of 308k steps were
  // rejected on it (measured).
  double error_norm(const State& err, const State& x0, const State& x1, double atol, double rtol) const {
    const double psi = x0[L::kAngle];
    const Vec2 n(std::cos(psi), std::sin(psi)), t(-n.y(), n.x());
    State y0 = x0, y1 = x1, e = err;
    store_kinematics<kStatorDof, kMotor, Rotor>(kinematics(x0, n, t), y0);
    store_kinematics<kStatorDof, kMotor, Rotor>(kinematics(x1), y1);
    e.template head<L::kSize>() = tangent_map(x0, n, t) * err.template head<L::kSize>();
    return std::sqrt((e.array() / (atol + rtol * y0.array().abs().max(y1.array().abs()))).square().mean());
  }

  void operator()(const State& x, State& dxdt, double t_s) const {
    ProfileScope scope(cartesian->rhs_time_s);
    const double delta = x[L::kDistance], psi = x[L::kAngle];
    const double delta_rate = x[L::kDistanceRate], psi_rate = x[L::kAngleRate];
    const Vec2 n(std::cos(psi), std::sin(psi)), t(-n.y(), n.x());
    const Kinematics k = kinematics(x, n, t);
    const DriveState reference = cartesian->segment.at(t_s);
    const StationModel& m = *cartesian->model;
    const DriveState d = m.drive_at(k, reference);
    const FreeLoads free = derivative_loads<L>(*cartesian->rotor, m, k, d, x, dxdt);
    const Accelerations a = cartesian->accelerations(d, geometry(x, n, t, d), free);
    if constexpr (kMotor) {
      cartesian->rotor->add_spin_share(free.unbalance_dir, a.spin_rad_per_s2, dxdt.tail(modal_count<L>(x)));
    }
    const Vec2 rel_acc = a.rotor - a.stator;
    dxdt[L::kDistance] = delta_rate;
    dxdt[L::kAngle] = psi_rate;
    dxdt[L::kDistanceRate] = rel_acc.dot(n) + delta * psi_rate * psi_rate;
    dxdt[L::kAngleRate] = (rel_acc.dot(t) - 2.0 * delta_rate * psi_rate) / delta;
    if constexpr (kStatorDof == 2) {
      dxdt.template segment<2>(L::kStatorPos) = k.stator_vel;
      dxdt.template segment<2>(L::kStatorVel) = a.stator;
    }
    spin_derivative<L>(m, k, reference, a.spin_rad_per_s2, dxdt);
  }

 private:
  // The accelerations at x (kinematics k, drive d), the block's loads included.
  Accelerations accelerations(const State& x, const Vec2& n, const Vec2& t, const Kinematics& k,
                              const DriveState& d) const {
    typename Rotor::ModalVector modal_acc(cartesian->rotor->modal_size());
    const FreeLoads free = cartesian->rotor->loads(*cartesian->model, k, d, x.tail(x.size() - L::kSize), modal_acc);
    return cartesian->accelerations(d, geometry(x, n, t, d), free);
  }
  mutable Matrix cartesian_jac_;
};

}  // namespace rotor_rub::core
