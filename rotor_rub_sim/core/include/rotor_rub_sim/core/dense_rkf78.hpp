// Runge-Kutta-Fehlberg 7(8) with step-size control, from Boost.Odeint, and a
// dense output for it: for tight tolerances, where Dormand-Prince 5(4) needs
// many short steps (on the paper run-up at rtol 1e-6 it takes 13 488
// derivative evaluations where dopri5 takes 24 364, rotor_rub_bench). The
// interface of DenseDopri5 but set_dt(), which only the penalty method uses.
//
// Odeint gives this pair no continuous extension, so the dense output is
// Hermite interpolation on the step's ends, which the mechanical structure
// of the state makes high order: every position q (a state whose derivative
// is another state, its velocity v) is the degree-7 polynomial that matches
// q, v = q', a = v' and the jerk j = a' at both ends; its velocity is that
// polynomial's derivative, so the two stay consistent. A state without such
// a pair (a motor drive's controller integral z) is the quintic matching z,
// z' and z''. The second derivative of the state (a' and z'') is a central
// difference of the derivative along the solution's tangent, two
// derivative evaluations per step: 15 per step in all, where 13 buy the step.
// Interpolation error for a motion of amplitude A and angular frequency w
// over a step h: A (w h)^8 / 10321920 in position (4e-10 A at w h = 0.5,
// 1e-7 A at w h = 1; the quintic without the jerk would be A (w h)^6 /
// 46080, 900 times more at w h = 0.5: the impact speeds of a bouncing rotor
// at rtol 1e-10 missed by 2e-8 m/s with it).
#pragma once

#include <array>
#include <boost/numeric/odeint.hpp>
#include <boost/numeric/odeint/external/eigen/eigen.hpp>
#include <cmath>
#include <utility>

#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

// A state layout's (model.hpp, constrained_dynamics.hpp) second-order
// pairs {q, v = q'}: its kDof positions, each followed kDof places later by
// its velocity, and a motor drive's spin angle and speed.
template <class Layout>
struct SecondOrderPairs {
  static constexpr int kCount = Layout::kDof + (Layout::kSpinSize > 0 ? 1 : 0);
  static std::array<std::pair<int, int>, kCount> pairs() {
    std::array<std::pair<int, int>, kCount> p{};
    for (int i = 0; i < Layout::kDof; ++i) p[i] = {i, Layout::kDof + i};
    if constexpr (Layout::kSpinSize > 0) p[Layout::kDof] = {Layout::kSpinAngle, Layout::kSpinSpeed};
    return p;
  }
};

template <class Layout>
class DenseRkf78 {
 public:
  using State = typename Layout::State;
  using Stepper = boost::numeric::odeint::runge_kutta_fehlberg78<State, double, State, double,
                                                                 boost::numeric::odeint::vector_space_algebra>;
  static_assert(2 * Layout::kDof + Layout::kSpinSize == State::RowsAtCompileTime, "positions, velocities, spin");
  using ErrorChecker =
      boost::numeric::odeint::default_error_checker<double, boost::numeric::odeint::vector_space_algebra,
                                                    boost::numeric::odeint::default_operations>;
  using Controlled = boost::numeric::odeint::controlled_runge_kutta<Stepper, ErrorChecker>;
  // New stages per attempt: 13 less the first, which is the derivative at
  // the step's start (kept from the last step's end, as FSAL methods do).
  static constexpr int kStagesPerAttempt = 12;
  // The central difference's step for the state's second derivative [s]:
  // its truncation error is (kJerkStep_s w)^2 / 6 of the jerk (1.5e-8 at
  // 300 rad/s); its rounding error 1e-16 |x| / (kJerkStep_s |x'|) (1e-9 for
  // a contact angle of 3000 rad turning at 300 rad/s; a one-sided 1e-9 s
  // difference lost 1e-6 there, which moved a steady rub's F_n by 1e-6).
  static constexpr double kJerkStep_s = 1e-6;

  // The error is measured as in DenseDopri5: atol + rtol |x| per component.
  // (GCC's -Wmaybe-uninitialized from odeint's stage buffers: see DenseDopri5.)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
  DenseRkf78(double atol, double rtol, double min_step_s, long max_steps)
      : controlled_(ErrorChecker(atol, rtol, 1.0, 0.0)),
        min_step_s_(min_step_s),
        max_steps_(max_steps),
        pairs_(SecondOrderPairs<Layout>::pairs()) {
    first_order_.fill(true);
    for (const auto& [q, v] : pairs_) first_order_[q] = first_order_[v] = false;
  }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

  template <class System>
  void initialize(System& sys, const State& x, double t_s, double dt_s, RunStats& stats) {
    x_new_ = x_old_ = x;
    t_new_ = t_old_ = t_s;
    sys(x_new_, dxdt_new_, t_new_);
    second_derivative(sys, x_new_, dxdt_new_, t_new_, ddx_new_);
    dxdt_old_ = dxdt_new_;
    ddx_old_ = ddx_new_;
    stats.rhs_evals += 3;
    dt_ = dt_s;
  }

  // One accepted step; throws MethodFailure (stalled, diverged) as DenseDopri5.
  template <class System>
  void do_step(System& sys, RunStats& stats) {
    x_old_ = x_new_;
    dxdt_old_ = dxdt_new_;
    ddx_old_ = ddx_new_;
    t_old_ = t_new_;
    double t = t_new_;
    for (;;) {
      check_step_budget(stats, max_steps_, dt_, min_step_s_, t);
      const auto result = controlled_.try_step(sys, x_old_, dxdt_old_, t, x_new_, dt_);
      stats.rhs_evals += kStagesPerAttempt;
      if (result == boost::numeric::odeint::success) break;
      ++stats.rejected_steps;
    }
    t_new_ = t;
    ++stats.steps;
    if (!x_new_.allFinite()) throw MethodFailure(FailureClass::kDiverged, t_new_, "non-finite state");
    sys(x_new_, dxdt_new_, t_new_);  // the dense output's end derivative and the next step's first stage
    second_derivative(sys, x_new_, dxdt_new_, t_new_, ddx_new_);
    stats.rhs_evals += 3;
  }

  // Undo the last accepted step and retry it with dt_s (a method's own rejection).
  void retreat(double dt_s, RunStats& stats) {
    x_new_ = x_old_;
    dxdt_new_ = dxdt_old_;
    ddx_new_ = ddx_old_;
    t_new_ = t_old_;
    dt_ = dt_s;
    --stats.steps;
    ++stats.rejected_steps;
  }

  void state_at(double t_s, State& x) const {
    if (t_new_ == t_old_) {  // no step yet: the initial state
      x = x_new_;
      return;
    }
    const double h = t_new_ - t_old_, s = (t_s - t_old_) / h;
    const double s2 = s * s, s3 = s2 * s, s4 = s3 * s, s5 = s4 * s, s6 = s5 * s, s7 = s6 * s;
    // Degree-7 Hermite basis: the weights of q, h v, h^2 a, h^3 j at the
    // start (0) and the end (1), and their d/ds for the velocities.
    const double q1 = 35 * s4 - 84 * s5 + 70 * s6 - 20 * s7, v0 = s - 20 * s4 + 45 * s5 - 36 * s6 + 10 * s7,
                 a0 = 0.5 * s2 - 5 * s4 + 10 * s5 - 7.5 * s6 + 2 * s7,
                 j0 = s3 / 6 - 2 * s4 / 3 + s5 - 2 * s6 / 3 + s7 / 6, v1 = -15 * s4 + 39 * s5 - 34 * s6 + 10 * s7,
                 a1 = 2.5 * s4 - 7 * s5 + 6.5 * s6 - 2 * s7, j1 = -s4 / 6 + s5 / 2 - s6 / 2 + s7 / 6;
    const double dq0 = -140 * s3 + 420 * s4 - 420 * s5 + 140 * s6, dv0 = 1 - 80 * s3 + 225 * s4 - 216 * s5 + 70 * s6,
                 da0 = s - 20 * s3 + 50 * s4 - 45 * s5 + 14 * s6,
                 dj0 = 0.5 * s2 - 8 * s3 / 3 + 5 * s4 - 4 * s5 + 7 * s6 / 6,
                 dv1 = -60 * s3 + 195 * s4 - 204 * s5 + 70 * s6, da1 = 10 * s3 - 35 * s4 + 39 * s5 - 14 * s6,
                 dj1 = -2 * s3 / 3 + 2.5 * s4 - 3 * s5 + 7 * s6 / 6;
    const double hh = h * h, hhh = hh * h;
    for (const auto& [q, v] : pairs_) {
      // q0 q_old + q1 q_new with q0 = 1 - q1, as q_old + q1 (q_new - q_old).
      x[q] = x_old_[q] + q1 * (x_new_[q] - x_old_[q]) + h * v0 * x_old_[v] + hh * a0 * dxdt_old_[v] +
             hhh * j0 * ddx_old_[v] + h * v1 * x_new_[v] + hh * a1 * dxdt_new_[v] + hhh * j1 * ddx_new_[v];
      // dq1 = -dq0: the difference first, so that an angle that keeps
      // growing (psi, phi) does not lose eps |q| / h to cancellation.
      x[v] = dq0 * (x_old_[q] - x_new_[q]) / h + dv0 * x_old_[v] + dv1 * x_new_[v] +
             h * (da0 * dxdt_old_[v] + da1 * dxdt_new_[v]) + hh * (dj0 * ddx_old_[v] + dj1 * ddx_new_[v]);
    }
    // Quintic Hermite for first-order states: z, h z', h^2 z'' at both ends.
    const double f0 = 1 - 10 * s3 + 15 * s4 - 6 * s5, f1 = s - 6 * s3 + 8 * s4 - 3 * s5,
                 f2 = 0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5, f3 = 1 - f0, f4 = -4 * s3 + 7 * s4 - 3 * s5,
                 f5 = 0.5 * s3 - s4 + 0.5 * s5;
    for (int i = 0; i < static_cast<int>(first_order_.size()); ++i) {
      if (first_order_[i]) {
        x[i] = f0 * x_old_[i] + h * f1 * dxdt_old_[i] + hh * f2 * ddx_old_[i] + f3 * x_new_[i] + h * f4 * dxdt_new_[i] +
               hh * f5 * ddx_new_[i];
      }
    }
  }

  double t_old() const { return t_old_; }
  double t_new() const { return t_new_; }
  double dt() const { return dt_; }
  const State& x_old() const { return x_old_; }
  const State& x_new() const { return x_new_; }

 private:
  mutable Controlled controlled_;
  double min_step_s_;
  long max_steps_;
  std::array<std::pair<int, int>, SecondOrderPairs<Layout>::kCount> pairs_;
  std::array<bool, State::RowsAtCompileTime> first_order_{};
  // The state's second derivative d(dx/dt)/dt along the solution: the
  // central difference of the derivative along (dx/dt, 1) (kJerkStep_s).
  template <class System>
  static void second_derivative(System& sys, const State& x, const State& dxdt, double t_s, State& ddx) {
    State before, after;
    sys(State(x - kJerkStep_s * dxdt), before, t_s - kJerkStep_s);
    sys(State(x + kJerkStep_s * dxdt), after, t_s + kJerkStep_s);
    ddx = (after - before) / (2.0 * kJerkStep_s);
  }

  State x_old_, x_new_, dxdt_old_, dxdt_new_, ddx_old_, ddx_new_;
  double t_old_ = 0.0, t_new_ = 0.0, dt_ = 1e-5;
};

}  // namespace rotor_rub::core
