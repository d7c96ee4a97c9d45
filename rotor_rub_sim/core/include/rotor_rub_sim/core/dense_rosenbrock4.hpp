// The stiff option (penalty method): Boost.Odeint's Rosenbrock 4(3) with its
// step controller and dense output, behind the same interface as
// DenseDopri5. Odeint's Rosenbrock stepper works on ublas containers, so the
// fixed-size Eigen state is copied in and out (buffers sized at start and at
// restarts only; no allocation per step). The Jacobian is formed by forward
// differences of the same right-hand side every method uses, so the model
// stays in one place.
#pragma once

#include <boost/numeric/odeint.hpp>
#include <boost/numeric/odeint/stepper/rosenbrock4.hpp>
#include <boost/numeric/odeint/stepper/rosenbrock4_controller.hpp>
#include <cmath>
#include <optional>
#include <type_traits>
#include <utility>

#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

template <class State>
class DenseRosenbrock4 {
 public:
  static constexpr int kSize = State::RowsAtCompileTime;
  using UVector = boost::numeric::ublas::vector<double>;
  using UMatrix = boost::numeric::ublas::matrix<double>;
  using Controller = boost::numeric::odeint::rosenbrock4_controller<boost::numeric::odeint::rosenbrock4<double>>;

  DenseRosenbrock4(double atol, double rtol, double min_step_s, long max_steps)
      : atol_(atol),
        rtol_(rtol),
        controller_(std::in_place, atol, rtol),
        min_step_s_(min_step_s),
        max_steps_(max_steps),
        ux_old_(kSize),
        ux_new_(kSize) {}

  template <class System>
  void initialize(System& /*sys*/, const State& x, double t_s, double dt_s, RunStats& /*stats*/) {
    x_old_ = x_new_ = x;
    to_ublas(x, ux_new_);
    ux_old_ = ux_new_;
    t_old_ = t_new_ = t_s;
    dt_ = dt_s;
    controller_.emplace(atol_, rtol_);  // forget the old step history
  }

  template <class System>
  void do_step(System& sys, RunStats& stats) {
    ux_old_ = ux_new_;
    x_old_ = x_new_;
    t_old_ = t_new_;
    double t = t_new_;
    auto rhs = [&sys, &stats](const UVector& ux, UVector& udxdt, double tt) {
      State x, dxdt;
      from_ublas(ux, x);
      sys(x, dxdt, tt);
      ++stats.rhs_evals;
      to_ublas(dxdt, udxdt);
    };
    auto jac = [&sys, &stats](const UVector& ux, UMatrix& J, double tt, UVector& dfdt) {
      State x, f0, f1;
      from_ublas(ux, x);
      sys(x, f0, tt);
      for (int j = 0; j < kSize; ++j) {
        // Forward difference with the step scaled to the component: the
        // Jacobian only steers the implicit stages; its error does not enter
        // the solution beyond the controller's estimate.
        const double h = 1e-7 * std::max(std::abs(x[j]), 1e-6);
        State xp = x;
        xp[j] += h;
        sys(xp, f1, tt);
        for (int i = 0; i < kSize; ++i) J(i, j) = (f1[i] - f0[i]) / h;
      }
      const double ht = 1e-7 * std::max(std::abs(tt), 1e-3);
      sys(x, f1, tt + ht);
      for (int i = 0; i < kSize; ++i) dfdt[i] = (f1[i] - f0[i]) / ht;
      stats.rhs_evals += kSize + 2;
      ++stats.jacobian_evals;
    };
    auto system = std::make_pair(rhs, jac);
    for (;;) {
      check_step_budget(stats, max_steps_, dt_, min_step_s_, t);
      const auto result = controller_->try_step(system, ux_old_, t, ux_new_, dt_);
      if (result == boost::numeric::odeint::success) break;
      ++stats.rejected_steps;
    }
    controller_->stepper().prepare_dense_output();
    t_new_ = t;
    from_ublas(ux_new_, x_new_);
    ++stats.steps;
    if (!x_new_.allFinite()) throw MethodFailure(FailureClass::kDiverged, t_new_, "non-finite state");
  }

  void state_at(double t_s, State& x) const {
    if (t_new_ == t_old_) {
      x = x_new_;
      return;
    }
    UVector ux(kSize);
    controller_->stepper().calc_state(t_s, ux, ux_old_, t_old_, ux_new_, t_new_);
    from_ublas(ux, x);
  }

  double t_old() const { return t_old_; }
  double t_new() const { return t_new_; }
  double dt() const { return dt_; }
  void set_dt(double dt_s) { dt_ = dt_s; }

 private:
  static void to_ublas(const State& x, UVector& u) {
    for (int i = 0; i < kSize; ++i) u[i] = x[i];
  }
  static void from_ublas(const UVector& u, State& x) {
    for (int i = 0; i < kSize; ++i) x[i] = u[i];
  }

  double atol_, rtol_;
  mutable std::optional<Controller> controller_;  // not assignable: re-emplaced on restart
  double min_step_s_;
  long max_steps_;
  UVector ux_old_, ux_new_;
  State x_old_, x_new_;
  double t_old_ = 0.0, t_new_ = 0.0, dt_ = 1e-5;
};

template <class Integrator>
struct is_implicit : std::false_type {};
template <class State>
struct is_implicit<DenseRosenbrock4<State>> : std::true_type {};

}  // namespace rotor_rub::core
