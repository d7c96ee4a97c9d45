// The high-order explicit integrators, with a dense output: Runge-Kutta-
// Fehlberg 7(8) (Boost.Odeint's, integrator rkf78) and Dormand-Prince
// 8(5,3) (dop853.hpp, integrator dop853), for tight tolerances, where
// Dormand-Prince 5(4) needs many short steps (the measured costs:
// docs/benchmarks.md, rotor_rub_bench). The interface of DenseDopri5 but
// set_dt(), which only the penalty method uses.
//
// Neither pair's own continuous extension is used (odeint gives rkf78
// none; dop853's costs 3 more stages), so the dense output is Hermite
// interpolation on the step's ends, which the mechanical structure
// of the state makes high order: every position q (a state whose derivative
// is another state, its velocity v) is the degree-7 polynomial that matches
// q, v = q', a = v' and the jerk j = a' at both ends; its velocity is that
// polynomial's derivative, so the two stay consistent. A state without such
// a pair (a motor drive's controller integral z) is the quintic matching z,
// z' and z''. The second derivative of the state (a' and z'') is the
// system's closed form where it has one (free flight and contact under the
// prescribed drive: from the step end's own evaluation, no extra one), else
// a central difference of the derivative along the solution's tangent, two
// derivative evaluations per step: 15 per step in all for rkf78, where 13
// buy the step (14 for dop853, where 12 do). A system whose derivative has a
// kink near a step's end computes its own (the iteration method's engaged
// regime: its force is clamped at zero past a lift-off; three evaluations
// where a kink is within the difference's reach).
// Interpolation error for a motion of amplitude A and angular frequency w
// over a step h: A (w h)^8 / 10321920 in position (4e-10 A at w h = 0.5,
// 1e-7 A at w h = 1; the quintic without the jerk would be A (w h)^6 /
// 46080, 900 times more at w h = 0.5: the impact speeds of a bouncing rotor
// at rtol 1e-10 missed by 2e-8 m/s with it).
#pragma once

#include <algorithm>
#include <array>
#include <boost/numeric/odeint.hpp>
#include <boost/numeric/odeint/external/eigen/eigen.hpp>
#include <cmath>
#include <type_traits>
#include <utility>

#include "integrators/dop853.hpp"
#include "integrators/step_ends.hpp"
#include "rotor_rub_sim/core/model.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

// The difference's step for the state's second derivative [s] (where no
// closed form is known): a central difference's truncation error is
// (kHermiteJerkStep_s w)^2 / 6 of the jerk (1.5e-8 at 300 rad/s); its
// rounding error 1e-16 |x| / (kHermiteJerkStep_s |x'|) (1e-9 for a contact
// angle of 3000 rad turning at 300 rad/s; a one-sided 1e-9 s difference lost
// 1e-6 there, which moved a steady rub's F_n by 1e-6).
inline constexpr double kHermiteJerkStep_s = 1e-6;

// Which end of a step an instant is: a system that computes its own end
// derivatives (kOwnEndDerivatives) may take them from the step's side.
enum class StepEnd { kStart, kEnd };

// A state layout's (model.hpp, constrained_dynamics.hpp) second-order
// pairs {q, v = q'}: its kDof positions, each followed kDof places later by
// its velocity, a motor drive's spin angle and speed, and a flexible
// rotor's modal coordinates, each followed n places later by its rate.
template <class Layout>
struct SecondOrderPairs {
  static constexpr int kMaxCount = Layout::kDof + (Layout::kSpinSize > 0 ? 1 : 0) +
                                   (kHasModalBlock<typename Layout::State> ? kMaxModalCoordinates : 0);
  // Fills p for a state of `size` entries; returns the count.
  static int pairs(int size, std::array<std::pair<int, int>, kMaxCount>& p) {
    int count = 0;
    for (int i = 0; i < Layout::kDof; ++i) p[count++] = {i, Layout::kDof + i};
    if constexpr (Layout::kSpinSize > 0) p[count++] = {Layout::kSpinAngle, Layout::kSpinSpeed};
    const int n = (size - Layout::kSize) / 2;
    for (int i = 0; i < n; ++i) p[count++] = {Layout::kModal + i, Layout::kModal + n + i};
    return count;
  }
};

// Boost.Odeint's Runge-Kutta-Fehlberg 7(8) under its controlled stepper,
// its error measured as DenseDopri5's: atol + rtol |x| per component (max
// norm).
template <class State>
class OdeintRkf78 {
 public:
  using Stepper = boost::numeric::odeint::runge_kutta_fehlberg78<State, double, State, double,
                                                                 boost::numeric::odeint::vector_space_algebra>;
  using ErrorChecker =
      boost::numeric::odeint::default_error_checker<double, boost::numeric::odeint::vector_space_algebra,
                                                    boost::numeric::odeint::default_operations>;
  using Controlled = boost::numeric::odeint::controlled_runge_kutta<Stepper, ErrorChecker>;
  // New stages per attempt: 13 less the first, which is the derivative at
  // the step's start (kept from the last step's end, as FSAL methods do).
  static constexpr int kStagesPerAttempt = 12;

  // (GCC's -Wmaybe-uninitialized from odeint's stage buffers: see DenseDopri5.)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
  OdeintRkf78(double atol, double rtol) : controlled_(ErrorChecker(atol, rtol, 1.0, 0.0)) {}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

  template <class System>
  bool try_step(System& sys, const State& x, const State& dxdt, double& t, State& x_out, double& dt) {
    return controlled_.try_step(sys, x, dxdt, t, x_out, dt) == boost::numeric::odeint::success;
  }

 private:
  Controlled controlled_;
};

// The dense high-order integrator on a stepping Engine (OdeintRkf78,
// Dop853): the engine's steps, the Hermite dense output of the header.
template <class Layout, class Engine>
class DenseHighOrder : public StepEnds<typename Layout::State> {
  using Ends = StepEnds<typename Layout::State>;
  using Ends::dt_;
  using Ends::dxdt_new_;
  using Ends::dxdt_old_;
  using Ends::max_steps_;
  using Ends::min_step_s_;
  using Ends::t_new_;
  using Ends::t_old_;
  using Ends::x_new_;
  using Ends::x_old_;

 public:
  using State = typename Layout::State;
  static_assert(2 * Layout::kDof + Layout::kSpinSize == Layout::kSize, "positions, velocities, spin");
  static constexpr int kStagesPerAttempt = Engine::kStagesPerAttempt;
  DenseHighOrder(double atol, double rtol, double min_step_s, long max_steps)
      : Ends(min_step_s, max_steps), engine_(atol, rtol) {}

  template <class System>
  void initialize(System& sys, const State& x, double t_s, double dt_s, RunStats& stats) {
    if (x.size() != size_) set_pairs(static_cast<int>(x.size()));
    x_new_ = x_old_ = x;
    t_new_ = t_old_ = t_s;
    stats.rhs_evals += end_derivatives(sys, x_new_, t_new_, StepEnd::kStart, dxdt_new_, ddx_new_);
    dxdt_old_ = dxdt_new_;
    ddx_old_ = ddx_new_;
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
      const double t_try = t, h = dt_;
      const bool accepted = engine_.try_step(sys, x_old_, dxdt_old_, t, x_new_, dt_);
      stats.rhs_evals += kStagesPerAttempt;
      if (!Ends::rejected_as_non_finite(t_try, h, t) && accepted) break;
      ++stats.rejected_steps;
    }
    t_new_ = t;
    ++stats.steps;
    // The dense output's end derivatives; the first is the next step's first stage.
    stats.rhs_evals += end_derivatives(sys, x_new_, t_new_, StepEnd::kEnd, dxdt_new_, ddx_new_);
    polynomial();
  }

  // The last accepted step's h rho(J) by the engine's stiffness test (Dop853::h_rho).
  double h_rho() const { return engine_.h_rho(x_new_, dxdt_new_, t_new_ - t_old_); }

  // Undo the last accepted step and retry it with dt_s (a method's own rejection).
  void retreat(double dt_s, RunStats& stats) {
    Ends::retreat_ends(dt_s, stats);
    ddx_new_ = ddx_old_;
  }

  // The dense output at t_s: the step's polynomial (polynomial()) by
  // Horner, its ends exactly the step's states.
  void state_at(double t_s, State& x) const {
    if (t_new_ == t_old_) {  // no step yet: the initial state
      x = x_new_;
      return;
    }
    const double s = (t_s - t_old_) / (t_new_ - t_old_);
    if (s == 1.0) {
      x = x_new_;
      return;
    }
    if (s == 0.0) {
      x = x_old_;
      return;
    }
    // Horner's rule as one expression: Eigen evaluates it in a single pass
    // over the state (a loop's first copy went through a non-inlined
    // unrolled copy). The same operations in the same order.
    static_assert(kDegree == 7, "the expression below is written for degree 7");
    x = x_old_ +
        s * (coef_[1] +
             s * (coef_[2] + s * (coef_[3] + s * (coef_[4] + s * (coef_[5] + s * (coef_[6] + s * coef_[7]))))));
  }

 private:
  // The state's second-order pairs and first-order entries for its size.
  void set_pairs(int size) {
    size_ = size;
    pair_count_ = SecondOrderPairs<Layout>::pairs(size, pairs_);
    first_order_.fill(false);
    std::fill(first_order_.begin(), first_order_.begin() + size, true);
    for (int k = 0; k < pair_count_; ++k) first_order_[pairs_[k].first] = first_order_[pairs_[k].second] = false;
  }

  Engine engine_;
  int size_ = -1;
  int pair_count_ = 0;
  std::array<std::pair<int, int>, SecondOrderPairs<Layout>::kMaxCount> pairs_{};
  std::array<bool, State::MaxRowsAtCompileTime> first_order_{};
  // The derivative dx/dt at a step's end and the state's second derivative
  // d(dx/dt)/dt along the solution: the central difference of the
  // derivative along (dx/dt, 1) (kHermiteJerkStep_s). A system that computes
  // its own (kOwnEndDerivatives, end_derivatives(x, t, end, dxdt, ddx) returning
  // the derivative evaluations it spent) gives both instead: in closed form
  // from one evaluation (free flight and contact under the prescribed
  // drive), or by a difference that keeps to one side of a kink (the
  // iteration method's engaged regime). Returns the derivative evaluations
  // spent.
  template <class System>
  static int end_derivatives(System& sys, const State& x, double t_s, StepEnd end, State& dxdt, State& ddx) {
    // Every system states it (kOwnEndDerivatives, true or false): a missing
    // or misspelled flag fails to compile.
    if constexpr (System::kOwnEndDerivatives) {
      return sys.end_derivatives(x, t_s, end, dxdt, ddx);
    } else {
      sys(x, dxdt, t_s);
      State before, after;
      sys(State(x - kHermiteJerkStep_s * dxdt), before, t_s - kHermiteJerkStep_s);
      sys(State(x + kHermiteJerkStep_s * dxdt), after, t_s + kHermiteJerkStep_s);
      ddx = (after - before) / (2.0 * kHermiteJerkStep_s);
      return 3;
    }
  }

  // The step's dense output as x(t_old + s h) = x_old + sum_k coef_k s^k,
  // k = 1..7, from the Hermite data of both ends (the header's comment):
  // every position q the degree-7 polynomial matching q, v, a, j; its
  // velocity v = q' / h that polynomial's derivative; a first-order state
  // the quintic matching z, z', z''. Built once a step, so that each of the
  // step's ~10 dense evaluations (event scan, samples, location) is a Horner
  // pass over the state, not the basis evaluated per call. The coefficients come from
  // the ends' differences, not their values, so that an angle that keeps
  // growing (psi, phi) does not lose eps |q| / h to cancellation.
  static constexpr int kDegree = 7;
  void polynomial() {
    const double h = t_new_ - t_old_, hh = h * h, hhh = hh * h;
    for (auto& c : coef_) c.setZero(x_new_.size());
    for (int k = 0; k < pair_count_; ++k) {
      const auto [q, v] = pairs_[k];
      const double dq = x_new_[q] - x_old_[q];
      const double v0 = h * x_old_[v], a0 = hh * dxdt_old_[v], j0 = hhh * ddx_old_[v];
      const double v1 = h * x_new_[v], a1 = hh * dxdt_new_[v], j1 = hhh * ddx_new_[v];
      const std::array<double, kDegree + 1> p = {
          0.0,
          v0,
          0.5 * a0,
          j0 / 6.0,
          35.0 * dq - 20.0 * v0 - 5.0 * a0 - 2.0 * j0 / 3.0 - 15.0 * v1 + 2.5 * a1 - j1 / 6.0,
          -84.0 * dq + 45.0 * v0 + 10.0 * a0 + j0 + 39.0 * v1 - 7.0 * a1 + 0.5 * j1,
          70.0 * dq - 36.0 * v0 - 7.5 * a0 - 2.0 * j0 / 3.0 - 34.0 * v1 + 6.5 * a1 - 0.5 * j1,
          -20.0 * dq + 10.0 * v0 + 2.0 * a0 + j0 / 6.0 + 10.0 * v1 - 2.0 * a1 + j1 / 6.0};
      for (int k = 1; k <= kDegree; ++k) coef_[k][q] = p[k];
      // v(s) = (1 / h) sum_k k p_k s^(k-1) = v_old + sum_k (k + 1) p_(k+1) s^k / h.
      for (int k = 1; k < kDegree; ++k) coef_[k][v] = (k + 1) * p[k + 1] / h;
    }
    for (int i = 0; i < size_; ++i) {
      if (!first_order_[i]) continue;
      const double dz = x_new_[i] - x_old_[i];
      const double z0 = h * dxdt_old_[i], zz0 = hh * ddx_old_[i], z1 = h * dxdt_new_[i], zz1 = hh * ddx_new_[i];
      coef_[1][i] = z0;
      coef_[2][i] = 0.5 * zz0;
      coef_[3][i] = 10.0 * dz - 6.0 * z0 - 1.5 * zz0 - 4.0 * z1 + 0.5 * zz1;
      coef_[4][i] = -15.0 * dz + 8.0 * z0 + 1.5 * zz0 + 7.0 * z1 - zz1;
      coef_[5][i] = 6.0 * dz - 3.0 * z0 - 0.5 * zz0 - 3.0 * z1 + 0.5 * zz1;
    }
  }

  State ddx_old_, ddx_new_;                // the second derivatives at the ends
  std::array<State, kDegree + 1> coef_{};  // coef_[0] unused: x_old_
};

template <class Layout>
using DenseRkf78 = DenseHighOrder<Layout, OdeintRkf78<typename Layout::State>>;
template <class Layout>
using DenseDop853 = DenseHighOrder<Layout, Dop853<typename Layout::State>>;

}  // namespace rotor_rub::core
