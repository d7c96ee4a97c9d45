// Classic fixed-step Runge-Kutta 4 (Boost.Odeint's runge_kutta4 stepper)
// behind the DenseDopri5 interface, for the stability campaign: with no error
// control it shows where a fixed step h stops being stable on the stiff
// penalty contact. The theory (docs and scripts/plot_stability.py): in
// sustained contact the relative rotor-stator mode has eigenvalues
// lambda = omega_c (-zeta +- i sqrt(1 - zeta^2)), omega_c = sqrt(k_c / m_eff);
// RK4 is stable while |R(h lambda)| <= 1, R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24,
// i.e. h <= r(zeta) / omega_c with r = 2.828 for zeta = 0 (e = 1, imaginary
// axis), 2.616 at its lowest (zeta 0.53; rk4_stability.hpp). Overdamped
// (zeta > 1; e = 0 gives zeta = 4.81 up to k_c 1e9, contact_law.hpp) the
// eigenvalues are real, -omega_c (zeta +- sqrt(zeta^2 - 1)), and the bound
// is h <= 2.785 / (omega_c (zeta + sqrt(zeta^2 - 1))).
//
// Dense output: cubic Hermite on the step's end values and slopes (third
// order; the slope at the end is the next step's first stage, so it costs
// nothing extra). Divergence: a non-finite state, or one whose norm exceeds
// kDivergenceBound, ends the run as diverged (no physical state of this
// machine has positions of metres or speeds of km/s).
#pragma once

#include <boost/numeric/odeint.hpp>
#include <boost/numeric/odeint/external/eigen/eigen.hpp>
#include <cmath>
#include <cstdio>
#include <type_traits>

#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

template <class State>
class DenseRk4 {
 public:
  static constexpr Integrator kScheme = Integrator::kRk4;
  static constexpr double kDivergenceBound = 1e3;  // |x| in m and m/s
  using Stepper =
      boost::numeric::odeint::runge_kutta4<State, double, State, double, boost::numeric::odeint::vector_space_algebra>;

  DenseRk4(double step_s, long max_steps) : h_(step_s), max_steps_(max_steps) {}

  template <class System>
  void initialize(System& sys, const State& x, double t_s, double /*dt_s*/, RunStats& stats) {
    x_old_ = x_new_ = x;
    t_old_ = t_new_ = t_s;
    sys(x_new_, dxdt_new_, t_new_);
    ++stats.rhs_evals;
    dxdt_old_ = dxdt_new_;
  }

  template <class System>
  void do_step(System& sys, RunStats& stats) {
    check_step_budget(stats, max_steps_, h_, 0.0, t_new_);
    x_old_ = x_new_;
    dxdt_old_ = dxdt_new_;
    t_old_ = t_new_;
    stepper_.do_step(sys, x_old_, dxdt_old_, t_old_, x_new_, h_);  // k1 given: 3 new stages
    t_new_ = t_old_ + h_;
    sys(x_new_, dxdt_new_, t_new_);  // the end slope: dense output and the next k1
    stats.rhs_evals += 4;
    ++stats.steps;
    if (!x_new_.allFinite() || x_new_.norm() > kDivergenceBound) {
      char what[160];
      std::snprintf(what, sizeof what, "fixed step h = %.3g s is unstable: state norm %.3g exceeds %.3g", h_,
                    x_new_.norm(), kDivergenceBound);
      throw MethodFailure(FailureClass::kDiverged, t_new_, what);
    }
  }

  void state_at(double t_s, State& x) const {
    const double dt = t_new_ - t_old_;
    if (dt <= 0.0) {
      x = x_new_;
      return;
    }
    const double s = (t_s - t_old_) / dt, s2 = s * s, s3 = s2 * s;
    x = (2 * s3 - 3 * s2 + 1) * x_old_ + (s3 - 2 * s2 + s) * dt * dxdt_old_ + (-2 * s3 + 3 * s2) * x_new_ +
        (s3 - s2) * dt * dxdt_new_;
  }

  double t_old() const { return t_old_; }
  double t_new() const { return t_new_; }
  double dt() const { return h_; }
  void set_dt(double /*dt_s*/) {}  // the step is fixed
  const State& x_old() const { return x_old_; }
  const State& x_new() const { return x_new_; }

 private:
  Stepper stepper_;
  double h_;
  long max_steps_;
  State x_old_, x_new_, dxdt_old_, dxdt_new_;
  double t_old_ = 0.0, t_new_ = 0.0;
};

template <class T>
struct is_fixed_step : std::false_type {};
template <class State>
struct is_fixed_step<DenseRk4<State>> : std::true_type {};

}  // namespace rotor_rub::core
