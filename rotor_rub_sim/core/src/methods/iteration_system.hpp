// The iteration method's one system of equations: the station under the
// rotor's free loads and the contact force iterated at every evaluation
// (contact_force_solver.hpp), the jerk of its Hermite dense output, and the
// integrator of each regime. What its class template
// (iteration_method_impl.hpp) integrates, and how. Private to that
// header's units, as it is (an unnamed namespace).
#pragma once

#include <cmath>
#include <stdexcept>
#include <type_traits>

#include "integrators/dense_for.hpp"
#include "methods/contact_force_solver.hpp"
#include "methods/event_scanner.hpp"
#include "rotor/rotor_model.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"
#include "run/cost_profiler.hpp"

namespace rotor_rub::core {
namespace {

template <int kStatorDof, bool kMotor, class Rotor>
struct IterationSystem : FreeFlightJacobianHooks<FreeLayout<kStatorDof, kMotor, Rotor>, kMotor> {
  using L = FreeLayout<kStatorDof, kMotor, Rotor>;
  // The jerk for the Hermite dense output (DenseHighOrder): a difference
  // (the contact force is a root, its rate no closed form), end_derivatives.
  static constexpr bool kOwnEndDerivatives = true;
  const StationModel* model = nullptr;
  const Rotor* rotor = nullptr;
  const ContactForceSolver* solver = nullptr;
  SpeedSegment segment;
  bool engaged = false;
  FrictionMode mode;
  long* iterations = nullptr;
  double* rhs_time_s = nullptr;        // profiling only
  double* iteration_time_s = nullptr;  // profiling only

  ContactForces forces(const Kinematics& k, const DriveState& d, const ContactGeometry& g, const FreeLoads& free,
                       double t) const {
    if (!engaged) return {};
    ProfileScope scope(iteration_time_s);
    return solver->solve(k, d, g, free, mode, false, t, *iterations);
  }

  void operator()(const typename L::State& x, typename L::State& dxdt, double t) const { derivative(x, dxdt, t); }

  // The stiff integrator's Jacobian (integrator rosenbrock4, which runs free
  // flight only: IterationIntegrator): free, the system is the switching
  // method's free flight (free_jacobian; test_penalty_jacobian.cpp).
  using State = typename L::State;
  using typename FreeFlightJacobianHooks<L, kMotor>::Matrix;
  void jacobian(const State& x, double t, Matrix& jac, State& dfdt) const {
    static_assert(!kMotor, "the motor drive's Jacobian is differenced");
    if (engaged) throw std::logic_error("IterationSystem::jacobian: the engaged system's force is a root, no Jacobian");
    free_jacobian<L>(*rotor, *model, x, segment.at(t), jac, dfdt);
  }

  // The derivative and its rate along the solution at a step's end: the
  // central difference of the derivative along (dxdt, 1) over
  // kHermiteJerkStep_s, but from the step's side of a release. Engaged, the
  // force is clamped at zero where nothing needs to press (a kink): a
  // difference across it is the clamp's, not the step's, and would bend the
  // interpolant of a step that ends just before a lift-off into the stator
  // (PaperScene.IterationLocatesItsLiftOffs). Where the two points differ
  // in being pressed, the second-order one-sided difference into the step
  // is taken (one evaluation more): at a step's end the pressed side, also
  // where the end lies on the kink itself (a step redone to end on its
  // lift-off, whose own force may round to either side). At a step's start
  // with a lift-off less than kHermiteJerkStep_s ahead it is the released
  // side; that step is cut at the lift-off, shorter than 1 us, where the
  // jerk's weight (h^3) leaves nothing to see.
  int end_derivatives(const typename L::State& x, double t, StepEnd end, typename L::State& dxdt,
                      typename L::State& ddx) const {
    constexpr double h = kHermiteJerkStep_s;
    typename L::State before, after, far;
    derivative(x, dxdt, t);
    const bool pressed_before = derivative(x - h * dxdt, before, t - h) > 0.0;
    const bool pressed_after = derivative(x + h * dxdt, after, t + h) > 0.0;
    if (pressed_before == pressed_after) {
      ddx = (after - before) / (2.0 * h);
      return 3;
    }
    if (end == StepEnd::kEnd) {
      derivative(x - 2.0 * h * dxdt, far, t - 2.0 * h);
      ddx = (3.0 * dxdt - 4.0 * before + far) / (2.0 * h);
    } else {
      derivative(x + 2.0 * h * dxdt, far, t + 2.0 * h);
      ddx = (4.0 * after - far - 3.0 * dxdt) / (2.0 * h);
    }
    return 4;
  }

  // The derivative; returns the normal force [N] (0 free or released).
  double derivative(const typename L::State& x, typename L::State& dxdt, double t) const {
    ProfileScope scope(rhs_time_s);
    const Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
    const DriveState reference = segment.at(t);
    const DriveState d = model->drive_at(k, reference);
    const ContactGeometry g = model->contact_geometry(k, d);
    const FreeLoads free = derivative_loads<L>(*rotor, *model, k, d, x, dxdt);
    const ContactForces f = forces(k, d, g, free, t);
    const Accelerations a = model->accelerations(d, g, free, f.normal_N, f.tangential_N);
    // A motor's spin: the rotor's block takes its share of its acceleration.
    if constexpr (kMotor) rotor->add_spin_share(free.unbalance_dir, a.spin_rad_per_s2, dxdt.tail(modal_count<L>(x)));
    free_derivative<L>(*model, k, reference, a, dxdt);
    return f.normal_N;
  }
};

// The integrator for the integrator key kScheme: Dormand-Prince 5(4)
// (dopri5) or 8(5,3) with the Hermite dense output (dop853) in both regimes;
// for rosenbrock4, RODASP in free flight, whose Jacobian is in closed form
// (IterationSystem::jacobian), and dop853 engaged, whose iterated force has
// none: a flexible rotor's highest mode kept sets an explicit scheme's free
// steps by its stability (docs/rotors.md, "Speed at many modes"); for
// dop853_rosenbrock4, free flight on RODASP only where dop853's steps are
// bound by stability (dense_stiffness_switch.hpp). The regime's integrator
// is the one a restart initializes (the system's engaged); each regime scans
// at the points of the scheme that took its step (event_scanner.hpp).
template <class L, Integrator kScheme>
class IterationIntegrator {
 public:
  using State = typename L::State;
  static constexpr Integrator kEngagedScheme = explicit_partner(kScheme);
  using Free = DenseFor<L, kScheme>;
  using Engaged = DenseFor<L, kEngagedScheme>;
  static constexpr bool kOne = std::is_same_v<Free, Engaged>;
  static_assert(!std::is_void_v<Free>, "no dense-output integrator for this key (DenseFor)");
  static_assert(!is_implicit<Engaged>::value, "the iterated contact force has no Jacobian in closed form");
  static constexpr int kEngagedScanPoints = scan_points(kEngagedScheme);
  // The free step's scan points, by the scheme that took it.
  int free_scan_points() const { return scan_points(scheme_now<kScheme>(free_)); }

  IterationIntegrator(double atol, double rtol, double min_step_s, long max_steps)
      : free_(atol, rtol, min_step_s, max_steps), engaged_(atol, rtol, min_step_s, max_steps) {}

  // Starts the regime's integrator at x (the step proposal dt_s carried over).
  template <class System>
  void initialize(System& sys, const State& x, double t_s, double dt_s, RunStats& stats) {
    engaged_on_ = !kOne && sys.engaged;
    on([&](auto& i) { i.initialize(sys, x, t_s, dt_s, stats); });
  }
  template <class System>
  void do_step(System& sys, RunStats& stats) {
    on([&](auto& i) { i.do_step(sys, stats); });
  }
  void limit_dt(double max_dt_s) {
    on([&](auto& i) { i.limit_dt(max_dt_s); });
  }
  void retreat(double dt_s, RunStats& stats) {
    on([&](auto& i) { i.retreat(dt_s, stats); });
  }
  // At a segment's end or a live change (end_step_if_implicit).
  template <class System>
  void end_free_step_at(System& sys, double t_s, RunStats& stats) {
    if (!engaged_on_) end_step_if_implicit(free_, sys, t_s, stats);
  }
  void state_at(double t_s, State& x) const {
    on([&](const auto& i) { i.state_at(t_s, x); });
  }
  const State& x_old() const {
    return on([](const auto& i) -> const State& { return i.x_old(); });
  }
  const State& x_new() const {
    return on([](const auto& i) -> const State& { return i.x_new(); });
  }
  double t_old() const {
    return on([](const auto& i) { return i.t_old(); });
  }
  double t_new() const {
    return on([](const auto& i) { return i.t_new(); });
  }
  double dt() const {
    return on([](const auto& i) { return i.dt(); });
  }

 private:
  struct None {  // no engaged integrator: one runs both regimes (dopri5, dop853)
    None(double /*atol*/, double /*rtol*/, double /*min_step_s*/, long /*max_steps*/) {}
  };
  // f applied to the regime's integrator.
  template <class F>
  decltype(auto) on(F&& f) {
    if constexpr (kOne) {
      return f(free_);
    } else {
      return engaged_on_ ? f(engaged_) : f(free_);
    }
  }
  template <class F>
  decltype(auto) on(F&& f) const {
    if constexpr (kOne) {
      return f(free_);
    } else {
      return engaged_on_ ? f(engaged_) : f(free_);
    }
  }
  Free free_;
  std::conditional_t<kOne, None, Engaged> engaged_;  // rosenbrock4's dop853
  bool engaged_on_ = false;
};

}  // namespace
}  // namespace rotor_rub::core
