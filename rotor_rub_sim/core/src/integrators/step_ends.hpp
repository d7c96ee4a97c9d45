// The two ends of a dense integrator's last accepted step, and what the
// methods read of them, shared by DenseDopri5 (dense_dopri5.hpp) and
// DenseHighOrder (dense_high_order.hpp): the step's times and states, the
// next step's proposal, and undoing the step when a method rejects it for
// its own reasons (the iteration method, on penetration).
#pragma once

#include <cmath>

#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

// A trial step whose end is not finite is rejected and the next trial cut to
// kNonFiniteShrink of it, in every adaptive integrator: a step far beyond an
// explicit scheme's stability, such as a long step carried over from another
// integrator, overflows where a shorter one need not
// (DenseIntegrator.ANonFiniteTrialIsRejectedAndTheStepCut). Cut this way
// below min_step_s, the run diverged: throws MethodFailure.
inline constexpr double kNonFiniteShrink = 0.2;
inline double step_after_non_finite(double h_s, double min_step_s, double t_s) {
  const double next = h_s * kNonFiniteShrink;
  if (!(std::abs(next) >= min_step_s)) {
    throw MethodFailure(FailureClass::kDiverged, t_s, "non-finite state on every trial step down to min_step_s");
  }
  return next;
}

template <class State>
class StepEnds {
 public:
  double t_old() const { return t_old_; }
  double t_new() const { return t_new_; }
  double dt() const { return dt_; }  // the next step's proposal [s]
  // Caps the next step's proposal (a NaN or infinite cap: none).
  void limit_dt(double max_dt_s) {
    if (dt_ > max_dt_s) dt_ = max_dt_s;
  }
  const State& x_old() const { return x_old_; }
  const State& x_new() const { return x_new_; }

 protected:
  StepEnds(double min_step_s, long max_steps) : min_step_s_(min_step_s), max_steps_(max_steps) {}

  // After an attempt from t_try with step h: true when its end is not
  // finite and it is rejected here (t back to t_try, step_after_non_finite).
  bool rejected_as_non_finite(double t_try_s, double h_s, double& t_s) {
    if (x_new_.allFinite()) return false;
    t_s = t_try_s;
    dt_ = step_after_non_finite(h_s, min_step_s_, t_s);
    return true;
  }

  // Undo the last accepted step and retry it with dt_s: the ends and the
  // counts (a step less, a rejection more); the derived integrator restores
  // what else it keeps of the step's end.
  void retreat_ends(double dt_s, RunStats& stats) {
    x_new_ = x_old_;
    dxdt_new_ = dxdt_old_;
    t_new_ = t_old_;
    dt_ = dt_s;
    --stats.steps;
    ++stats.rejected_steps;
  }

  double min_step_s_;
  long max_steps_;
  State x_old_, x_new_, dxdt_old_, dxdt_new_;
  double t_old_ = 0.0, t_new_ = 0.0, dt_ = 1e-5;
};

}  // namespace rotor_rub::core
