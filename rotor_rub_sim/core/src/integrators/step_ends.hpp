// The two ends of a dense integrator's last accepted step, and what the
// methods read of them, shared by DenseDopri5 (dense_dopri5.hpp) and
// DenseHighOrder (dense_high_order.hpp): the step's times and states, the
// next step's proposal, and undoing the step when a method rejects it for
// its own reasons (the iteration method, on penetration).
#pragma once

#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

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
