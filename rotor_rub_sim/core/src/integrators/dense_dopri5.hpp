// Dormand-Prince 5(4) with step-size control and its free 4th-order dense
// output, on Boost.Odeint's controlled stepper, with the cost counted: the
// odeint dense-output driver hides rejected steps, this one reports them and
// lets a method reject a step for its own reasons (the iteration method does,
// on penetration).
#pragma once

#include <boost/numeric/odeint.hpp>
#include <boost/numeric/odeint/external/eigen/eigen.hpp>
#include <cmath>

#include "integrators/step_ends.hpp"
#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

template <class State>
class DenseDopri5 : public StepEnds<State> {
  using Ends = StepEnds<State>;
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
  static constexpr Integrator kScheme = Integrator::kDopri5;
  using Stepper = boost::numeric::odeint::runge_kutta_dopri5<State, double, State, double,
                                                             boost::numeric::odeint::vector_space_algebra>;
  using ErrorChecker =
      boost::numeric::odeint::default_error_checker<double, boost::numeric::odeint::vector_space_algebra,
                                                    boost::numeric::odeint::default_operations>;
  using Controlled = boost::numeric::odeint::controlled_runge_kutta<Stepper, ErrorChecker>;

  // The error is measured as atol + rtol |x| per component (a_dxdt = 0, as in
  // MATLAB's ode45), so tolerances mean what the paper's mean.
  //
  // GCC 12 at -O2 warns here, from inside Boost and Eigen, that odeint's
  // stepper copies its fixed-size Eigen stage buffers before their first use
  // (the controlled stepper is built from a default-constructed one); they are
  // written before they are read. Silenced for this constructor only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
  DenseDopri5(double atol, double rtol, double min_step_s, long max_steps)
      : Ends(min_step_s, max_steps), controlled_(ErrorChecker(atol, rtol, 1.0, 0.0)) {}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

  template <class System>
  void initialize(System& sys, const State& x, double t_s, double dt_s, RunStats& stats) {
    x_new_ = x;
    t_new_ = t_old_ = t_s;
    x_old_ = x;
    sys(x_new_, dxdt_new_, t_new_);
    ++stats.rhs_evals;
    dt_ = dt_s;
  }

  // One accepted step from the current end. Throws MethodFailure (stalled)
  // when the step size falls below the minimum or the step budget is spent,
  // (diverged) when every trial down to the minimum ended non-finite (odeint
  // accepts such a trial: its error is NaN; StepEnds rejects it).
  template <class System>
  void do_step(System& sys, RunStats& stats) {
    x_old_ = x_new_;
    dxdt_old_ = dxdt_new_;
    t_old_ = t_new_;
    double t = t_new_;
    for (;;) {
      check_step_budget(stats, max_steps_, dt_, min_step_s_, t);
      const double t_try = t, h = dt_;
      const auto result = controlled_.try_step(sys, x_old_, dxdt_old_, t, x_new_, dxdt_new_, dt_);
      stats.rhs_evals += 6;  // dopri5's FSAL: six new stages per attempt
      if (!Ends::rejected_as_non_finite(t_try, h, t) && result == boost::numeric::odeint::success) break;
      ++stats.rejected_steps;
    }
    t_new_ = t;
    ++stats.steps;
  }

  // Undo the last accepted step and retry it with dt_s (a method's own rejection).
  void retreat(double dt_s, RunStats& stats) { Ends::retreat_ends(dt_s, stats); }

  void state_at(double t_s, State& x) const {
    if (t_new_ == t_old_) {  // no step yet: the initial state
      x = x_new_;
      return;
    }
    controlled_.stepper().calc_state(t_s, x, x_old_, dxdt_old_, t_old_, x_new_, dxdt_new_, t_new_);
  }

  void set_dt(double dt_s) { dt_ = dt_s; }

 private:
  mutable Controlled controlled_;
};

}  // namespace rotor_rub::core
