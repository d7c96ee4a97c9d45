// The switching method's two systems of equations, free flight and the rotor
// held on the bore, each regime's integrator and its event functions' values:
// what its class template (switching_method_impl.hpp) integrates and scans.
// Private to that header's units, as it is (an unnamed namespace).
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

#include "integrators/dense_for.hpp"
#include "methods/constrained_dynamics.hpp"
#include "methods/event_scanner.hpp"
#include "rotor/rotor_model.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"
#include "run/cost_profiler.hpp"

namespace rotor_rub::core {
namespace {

// Free flight: the station (model) under the rotor's free loads, and the
// rotor's own block (rotor_model.hpp).
template <int kStatorDof, bool kMotor, class Rotor>
struct FreeFlightSystem : FreeFlightJacobianHooks<FreeLayout<kStatorDof, kMotor, Rotor>, kMotor> {
  using L = FreeLayout<kStatorDof, kMotor, Rotor>;
  using State = typename L::State;
  const StationModel* model;
  const Rotor* rotor = nullptr;
  SpeedSegment segment;
  double* rhs_time_s = nullptr;  // profiling only
  // The stiff integrator's Jacobian (integrator rosenbrock4, which runs free
  // flight only): under the prescribed drive free flight is linear, its
  // Jacobian the rotor model's free loads' and the stator's spring and
  // damper (free_jacobian). test_penalty_jacobian.cpp holds it against
  // differences (ClosedFormMatchesDifferencesInEveryMode, FlexibleRotors...).
  using typename FreeFlightJacobianHooks<L, kMotor>::Matrix;
  void jacobian(const State& x, double t, Matrix& jac, State& dfdt) const {
    static_assert(!kMotor, "the motor drive's Jacobian is differenced");
    free_jacobian<L>(*rotor, *model, x, segment.at(t), jac, dfdt);
  }
  void operator()(const State& x, State& dxdt, double t) const {
    ProfileScope scope(rhs_time_s);
    const Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
    if constexpr (kMotor) {
      // The spin's acceleration and the rotor's depend on each other
      // (model.hpp): the free loads with the spin coupling, then the block's
      // share of the spin's acceleration.
      const DriveState reference = segment.at(t);
      const DriveState d = model->drive_at(k, reference);
      const FreeLoads free = derivative_loads<L>(*rotor, *model, k, d, x, dxdt);
      const Accelerations a = model->accelerations(d, ContactGeometry(), free, 0.0, 0.0);
      rotor->add_spin_share(free.unbalance_dir, a.spin_rad_per_s2, dxdt.tail(modal_count<L>(x)));
      dxdt.template segment<2>(L::kRotorPos) = k.rotor_vel;
      if constexpr (kStatorDof == 2) dxdt.template segment<2>(L::kStatorPos) = k.stator_vel;
      dxdt.template segment<2>(L::kRotorVel) = a.rotor;
      if constexpr (kStatorDof == 2) dxdt.template segment<2>(L::kStatorVel) = a.stator;
      spin_derivative<L>(*model, k, reference, a.spin_rad_per_s2, dxdt);
    } else {
      const DriveState d = segment.at(t);
      derivative(x, k, d, unbalance_at(d.angle_rad), dxdt);
    }
  }
  // The derivative and the state's second derivative at a step's end, from
  // one sin/cos of the unbalance (DenseHighOrder's jerk, instead of two
  // derivative evaluations): under the prescribed drive the free forces are
  // linear in the state (model.hpp), so x'' is the derivative's own linear
  // map applied to dxdt, plus the unbalance's rate.
  static constexpr bool kOwnEndDerivatives = !kMotor;
  int end_derivatives(const State& x, double t, StepEnd /*end*/, State& dxdt, State& ddx) const {
    static_assert(!kMotor, "the motor's spin couples: differenced instead");
    ProfileScope scope(rhs_time_s);
    const Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
    const DriveState d = segment.at(t);
    const Vec2 unbalance_dir = unbalance_at(d.angle_rad);
    derivative(x, k, d, unbalance_dir, dxdt);
    const int n = modal_count<L>(x);
    ddx.resize(x.size());  // before any entry is written
    ddx.template segment<2>(L::kRotorPos) = dxdt.template segment<2>(L::kRotorVel);
    ddx.segment(L::kModal, n) = dxdt.tail(n);
    ddx.template segment<2>(L::kRotorVel) = rotor->station_force_rate(*model, k, dxdt.template segment<2>(L::kRotorVel),
                                                                      d, unbalance_dir, dxdt.tail(2 * n), ddx.tail(n)) *
                                            model->inv_rotor_mass();
    if constexpr (kStatorDof == 2) {
      ddx.template segment<2>(L::kStatorPos) = dxdt.template segment<2>(L::kStatorVel);
      ddx.template segment<2>(L::kStatorVel) =
          model->stator_free_force_derivative(k, dxdt.template segment<2>(L::kStatorVel)) * model->inv_stator_mass();
    }
    return 1;  // one derivative evaluation; the jerk from the free forces' rates
  }
  // The unbalance's direction at the spin angle phi (StationModel::unbalance_dir).
  Vec2 unbalance_at(double angle_rad) const { return model->unbalance_dir(angle_rad); }

 private:
  void derivative(const State& x, const Kinematics& k, const DriveState& d, const Vec2& unbalance_dir,
                  State& dxdt) const {
    const int n = modal_count<L>(x);
    dxdt.resize(x.size());
    dxdt.segment(L::kModal, n) = x.tail(n);
    const Vec2 rotor_force = rotor->station_force(*model, k, d, unbalance_dir, x.tail(2 * n), dxdt.tail(n));
    dxdt.template segment<2>(L::kRotorPos) = k.rotor_vel;
    if constexpr (kStatorDof == 2) dxdt.template segment<2>(L::kStatorPos) = k.stator_vel;
    dxdt.template segment<2>(L::kRotorVel) = rotor_force * model->inv_rotor_mass();
    if constexpr (kStatorDof == 2) {
      dxdt.template segment<2>(L::kStatorVel) = model->stator_free_force(k) * model->inv_stator_mass();
    }
  }
};

template <int kStatorDof, bool kMotor, class Rotor>
struct ContactSystem {
  using L = ContactLayout<kStatorDof, kMotor, Rotor>;
  using Dynamics = ConstrainedDynamics<kStatorDof, kMotor, Rotor>;
  using Result = typename Dynamics::Result;
  Dynamics dynamics;
  SpeedSegment segment;
  double* rhs_time_s = nullptr;  // profiling only
  void operator()(const typename L::State& x, typename L::State& dxdt, double t) const {
    ProfileScope scope(rhs_time_s);
    dynamics.derivative(x, segment.at(t), dxdt);
  }
  // The derivative and the jerk in closed form (constrained_dynamics.hpp)
  // at a step's end from one evaluation.
  static constexpr bool kOwnEndDerivatives = !kMotor;
  int end_derivatives(const typename L::State& x, double t, StepEnd /*end*/, typename L::State& dxdt,
                      typename L::State& ddx) const {
    ProfileScope scope(rhs_time_s);
    const DriveState reference = segment.at(t);
    const Result r = dynamics.evaluate(x, reference);
    dynamics.derivative(x, r, reference, dxdt);
    dynamics.second_derivative(x, r, reference, ddx);
    return 1;  // one constrained-dynamics evaluation
  }
};

// Each regime's integrator for the integrator key kScheme: Dormand-Prince
// 5(4) (dopri5), one of the high-order pairs with Hermite dense output
// (dense_high_order.hpp: Runge-Kutta-Fehlberg 7(8), rkf78; Dormand-Prince
// 8(5,3), dop853); or RODASP (rosenbrock4, dense_rodasp.hpp) in free flight,
// whose Jacobian is in closed form (FreeFlightSystem), with dop853 in
// contact, whose constrained dynamics has none: a flexible rotor's modes
// kept set the explicit schemes' steps by their stability, not by the
// tolerance (docs/rotors.md, "Speed at many modes"); or dop853_rosenbrock4,
// whose free flight is on RODASP where dop853's steps are bound by stability
// (dense_stiffness_switch.hpp). Each regime scans for events at the points of
// the scheme that took its step (event_scanner.hpp).
template <class FL, class CL, Integrator kScheme>
struct SwitchingIntegrators {
  static constexpr Integrator kContactScheme = explicit_partner(kScheme);
  using Free = DenseFor<FL, kScheme>;
  using Contact = DenseFor<CL, kContactScheme>;
  static_assert(!std::is_void_v<Free>, "no dense-output integrator for this key (DenseFor)");
  static_assert(!is_implicit<Contact>::value, "the constrained dynamics has no Jacobian in closed form");
  static constexpr int kContactScanPoints = scan_points(kContactScheme);
};

enum class Regime { kFree, kContact };

// The event functions, each an event when it rises through 0. Free flight:
// kGap = delta - C. Contact: kGap = -F_n (lift-off), kSlipEnd = -s v_slide
// (the sliding stops), kBreakaway = |F_t,stick| - f F_n (the stick force
// leaves the cone). A function unused in the current regime is -infinity.
enum EventFunction { kGap = 0, kSlipEnd = 1, kBreakaway = 2, kEventFunctions = 3 };

struct EventValues {
  std::array<double, kEventFunctions> value;
  std::array<double, kEventFunctions> rate;  // d value / dt where known, else NaN
  // In contact, the rate of the unbalance's angle in the contact frame,
  // phi' - psi' [rad/s] (kMaxScanAngle_rad); NaN in free flight.
  double forcing_rate_rad_per_s = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace
}  // namespace rotor_rub::core
