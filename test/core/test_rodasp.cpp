// The stiff integrator (dense_rodasp.hpp) on closed forms, and against
// Boost.Odeint's rosenbrock4 it replaced: order on a non-autonomous forced
// oscillator and on the Prothero-Robinson problem (the contact's slow mode),
// dense output between the steps, and the penalty method through the paper
// scene's contacts at every tolerance from 1e-3 to 1e-10.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <cstdio>
#include <vector>

#include "integrators/dense_rodasp.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "test_support.hpp"

namespace rotor_rub {
namespace {

using core::DenseRodasp;

// Prothero-Robinson: y' = lambda (y - sin(w t)) + w cos(w t), y(0) = 0, whose
// solution is sin(w t) for every lambda. lambda -1e4 and w 100 rad/s put
// h |lambda| between 1 and 100 at these tolerances: the paper scene's
// contact (slow mode -6.3e3 1/s, whirl ~280 rad/s).
constexpr double kLambda = -1e4;
constexpr double kOmega = 100.0;
using State1 = Eigen::Matrix<double, 1, 1>;
struct ProtheroRobinson {
  // No closed-form hooks (dense_rodasp.hpp): the integrator differences J.
  static constexpr bool kAnalyticJacobian = false, kSecondOrderJacobian = false, kOwnErrorNorm = false;
  void operator()(const State1& y, State1& dy, double t) const {
    dy[0] = kLambda * (y[0] - std::sin(kOmega * t)) + kOmega * std::cos(kOmega * t);
  }
};

struct Outcome {
  long steps = 0;
  double max_error = 0.0;    // at the steps' ends
  double dense_error = 0.0;  // at the dense output between them
};

template <class System, class State, class Exact>
Outcome integrate(const System& sys_in, State x, double tol, double t_end, Exact exact) {
  System sys = sys_in;
  DenseRodasp<State> integ(tol, tol, 1e-14, 10'000'000);
  core::RunStats stats;
  integ.initialize(sys, x, 0.0, 1e-5, stats);
  Outcome o;
  while (integ.t_new() < t_end) {
    integ.do_step(sys, stats);
    for (double s : {0.25, 0.5, 0.75, 1.0}) {
      const double t = integ.t_old() + s * (integ.t_new() - integ.t_old());
      State xi;
      integ.state_at(t, xi);
      const double e = (xi - exact(t)).template lpNorm<Eigen::Infinity>();
      (s == 1.0 ? o.max_error : o.dense_error) = std::max(s == 1.0 ? o.max_error : o.dense_error, e);
    }
  }
  o.steps = stats.steps;
  return o;
}

// Steps grow by 10^(3/4) = 5.6 over three decades of tolerance at order 4
// (error estimate h^4); at order 1 by 10^(3/2) = 32. Measured: 5.2 on the
// non-stiff oscillator. The bound 8 leaves room for the controller's rounding.
constexpr double kOrderFourStepGrowth = 8.0;
// On Prothero-Robinson at h |lambda| from 46 down to 3, RODASP's steps grow
// 14x (measured; partial order reduction remains in this transition range),
// odeint's rosenbrock4's 66x (605k steps at 1e-8 against RODASP's 3044).
constexpr double kProtheroRobinsonStepGrowth = 20.0;
// At the steps' ends the global error stays near the tolerance (measured
// 0.74 to 1.08 tol on both problems).
constexpr double kGlobalErrorPerTol = 3.0;
// The third-order continuous extension between steps: 3.2 to 3.4 tol on the
// oscillator (measured); on the stiff problem at h |lambda| ~ 46 it is the
// weak point: 64 tol at 1e-5, 8.8 tol at 1e-8 (measured).
constexpr double kDenseErrorPerTol = 10.0;
constexpr double kStiffDenseErrorPerTol = 100.0;

// A loose and a tight run of one problem: the steps' growth between them,
// and the errors at the steps' ends and between them, per tolerance.
void expect_runs(const Outcome& loose, double loose_tol, const Outcome& tight, double tight_tol, double max_growth,
                 double dense_error_per_tol) {
  EXPECT_LT(static_cast<double>(tight.steps) / loose.steps, max_growth)
      << loose.steps << " -> " << tight.steps << " steps";
  EXPECT_LT(loose.max_error, kGlobalErrorPerTol * loose_tol);
  EXPECT_LT(tight.max_error, kGlobalErrorPerTol * tight_tol);
  EXPECT_LT(loose.dense_error, dense_error_per_tol * loose_tol);
  EXPECT_LT(tight.dense_error, dense_error_per_tol * tight_tol);
}

TEST(Rodasp, ProtheroRobinsonStepsAndErrors) {
  auto exact = [](double t) { return State1(std::sin(kOmega * t)); };
  const Outcome loose = integrate(ProtheroRobinson{}, State1(0.0), 1e-5, 1.0, exact);
  const Outcome tight = integrate(ProtheroRobinson{}, State1(0.0), 1e-8, 1.0, exact);
  expect_runs(loose, 1e-5, tight, 1e-8, kProtheroRobinsonStepGrowth, kStiffDenseErrorPerTol);
}

// A forced, damped oscillator with a chirp-free forcing cos(W t) from rest:
// x'' + 2 z w x' + w^2 x = cos(W t). Closed form: the steady part
// (A cos W t + B sin W t) plus the homogeneous part that starts it from rest.
struct Forced {
  // No closed-form hooks (dense_rodasp.hpp): the integrator differences J.
  static constexpr bool kAnalyticJacobian = false, kSecondOrderJacobian = false, kOwnErrorNorm = false;
  static constexpr double w = 80.0, z = 0.01, W = 130.0;
  template <class State>  // fixed-size, or dynamic within a bound
  void operator()(const State& x, State& dx, double t) const {
    dx.resize(2);
    dx[0] = x[1];
    dx[1] = std::cos(W * t) - 2 * z * w * x[1] - w * w * x[0];
  }
  static Eigen::Vector2d exact(double t) {
    const double den = (w * w - W * W) * (w * w - W * W) + (2 * z * w * W) * (2 * z * w * W);
    const double A = (w * w - W * W) / den, B = 2 * z * w * W / den;
    const double wd = w * std::sqrt(1 - z * z), s = z * w;
    // x_h = e^{-s t}(C cos wd t + D sin wd t), x(0) = 0, x'(0) = 0.
    const double C = -A, D = (s * C - B * W) / wd;
    const double e = std::exp(-s * t);
    const double xh = e * (C * std::cos(wd * t) + D * std::sin(wd * t));
    const double vh = e * ((-s * C + wd * D) * std::cos(wd * t) + (-s * D - wd * C) * std::sin(wd * t));
    return {A * std::cos(W * t) + B * std::sin(W * t) + xh, -A * W * std::sin(W * t) + B * W * std::cos(W * t) + vh};
  }
};

TEST(Rodasp, FourthOrderOnANonAutonomousOscillator) {
  const Outcome loose = integrate(Forced{}, Eigen::Vector2d::Zero().eval(), 1e-6, 1.0, Forced::exact);
  const Outcome tight = integrate(Forced{}, Eigen::Vector2d::Zero().eval(), 1e-9, 1.0, Forced::exact);
  // The amplitude is ~1e-4 m, so atol = tol governs the errors.
  expect_runs(loose, 1e-6, tight, 1e-9, kOrderFourStepGrowth, kDenseErrorPerTol);
}

// A flexible rotor's state is dynamic within a bound (model.hpp), its J and
// LU too (dense_rodasp.hpp): on the same problem such a state takes the
// fixed-size run's steps and gives its results to rounding (Eigen's loops
// for the two sizes may sum in another order; 1e-15 of the amplitude).
TEST(Rodasp, ADynamicBoundedStateStepsAsTheFixedSizeOne) {
  using Bounded = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 8, 1>;
  DenseRodasp<Eigen::Vector2d> fixed(1e-8, 1e-8, 1e-14, 1'000'000);
  DenseRodasp<Bounded> bounded(1e-8, 1e-8, 1e-14, 1'000'000);
  core::RunStats fixed_stats, bounded_stats;
  const Forced sys;
  fixed.initialize(sys, Eigen::Vector2d::Zero().eval(), 0.0, 1e-5, fixed_stats);
  bounded.initialize(sys, Bounded::Zero(2).eval(), 0.0, 1e-5, bounded_stats);
  double worst = 0.0, largest = 0.0;
  while (fixed.t_new() < 1.0) {
    fixed.do_step(sys, fixed_stats);
    bounded.do_step(sys, bounded_stats);
    ASSERT_NEAR(bounded.t_new(), fixed.t_new(), 1e-12) << fixed_stats.steps;
    const double t = 0.5 * (fixed.t_old() + fixed.t_new());
    Eigen::Vector2d a;
    Bounded b;
    fixed.state_at(t, a);
    bounded.state_at(t, b);
    ASSERT_EQ(b.size(), 2);
    worst = std::max(worst, (a - b).lpNorm<Eigen::Infinity>());
    largest = std::max(largest, a.lpNorm<Eigen::Infinity>());
  }
  std::printf("bounded against fixed: %.3g of %.3g\n", worst, largest);
  EXPECT_EQ(bounded_stats.steps, fixed_stats.steps);
  EXPECT_EQ(bounded_stats.rejected_steps, fixed_stats.rejected_steps);
  EXPECT_EQ(bounded_stats.rhs_evals, fixed_stats.rhs_evals);
  EXPECT_LE(worst, 1e-15 * largest);
}

// Two coupled, damped oscillators, one mode stiff (about -1e4 1/s), under
// forcing in the velocity rows: x' = J x + (0, g(t)) with J = [0 I; A B].
// kClosed: the system gives J and df/dt (kAnalyticJacobian); kHalf:
// also declares the second-order form (the half-size solve).
template <bool kClosed, bool kHalf>
struct Coupled {
  using State4 = Eigen::Vector4d;
  using Matrix = Eigen::Matrix4d;
  static constexpr bool kAnalyticJacobian = kClosed;
  static constexpr bool kSecondOrderJacobian = kHalf;
  static constexpr bool kOwnErrorNorm = false;
  static Matrix jac() {
    Matrix j = Matrix::Zero();
    j.topRightCorner<2, 2>().setIdentity();
    j.bottomLeftCorner<2, 2>() << -6.4e3, 2.0e3, 1.5e3, -4.0e4;
    j.bottomRightCorner<2, 2>() << -3.0, 1.0, 0.5, -1.0e4;
    return j;
  }
  static Eigen::Vector2d g(double t) { return {std::cos(130.0 * t), 0.5 * std::sin(210.0 * t)}; }
  void operator()(const State4& x, State4& dx, double t) const {
    dx = jac() * x;
    dx.tail<2>() += g(t);
  }
  void jacobian(const State4& /*x*/, double t, Matrix& j, State4& dfdt) const {
    j = jac();
    dfdt << 0.0, 0.0, -130.0 * std::sin(130.0 * t), 0.5 * 210.0 * std::cos(210.0 * t);
  }
};

struct CoupledRun {
  std::vector<Eigen::Vector4d> first_steps;  // the ends of the first 5 steps
  Eigen::Vector4d at_end;                    // the dense output at 0.3 s
  long rhs_evals = 0, accepted = 0, attempts = 0;
};
template <class System>
CoupledRun coupled_run(double tol) {
  System sys;
  DenseRodasp<Eigen::Vector4d> integ(tol, tol, 1e-14, 1'000'000);
  core::RunStats stats;
  integ.initialize(sys, Eigen::Vector4d::Zero().eval(), 0.0, 1e-5, stats);
  CoupledRun r;
  Eigen::Vector4d x;
  while (integ.t_new() < 0.3) {
    integ.do_step(sys, stats);
    integ.state_at(integ.t_new(), x);
    if (r.first_steps.size() < 5) r.first_steps.push_back(x);
  }
  integ.state_at(0.3, r.at_end);
  r.rhs_evals = stats.rhs_evals;
  r.accepted = stats.steps;
  r.attempts = stats.steps + stats.rejected_steps;
  return r;
}

// The half-size solve is the full one rearranged: the same first steps to
// rounding (dropping its tau^2 A term moves them by 2.5e-7 relative; later
// the controller's choices drift apart by rounding, within the tolerance).
// Closed form and differences reach the tolerance against a tight run
// (measured 3e-9 at tol 1e-8, all three). The
// derivatives: 5 new stages an attempt, and a step's start derivative, plus
// kSize + 2 for differences.
TEST(Rodasp, SecondOrderSolveAndClosedFormMatchTheFullDifferencedStep) {
  constexpr double kTol = 1e-8;
  const CoupledRun fd = coupled_run<Coupled<false, false>>(kTol);
  const CoupledRun full = coupled_run<Coupled<true, false>>(kTol);
  const CoupledRun half = coupled_run<Coupled<true, true>>(kTol);
  const CoupledRun reference = coupled_run<Coupled<true, true>>(1e-12);
  ASSERT_EQ(full.first_steps.size(), 5u);
  for (std::size_t i = 0; i < full.first_steps.size(); ++i) {
    const double scale = full.first_steps[i].cwiseAbs().maxCoeff();
    EXPECT_LT((half.first_steps[i] - full.first_steps[i]).cwiseAbs().maxCoeff(), 1e-10 * scale) << "step " << i;
  }
  const double scale = reference.at_end.cwiseAbs().maxCoeff();
  for (const CoupledRun* r : {&fd, &full, &half}) {
    // atol = rtol = kTol: the error weight is kTol (1 + |x|); 0.3 s is on the dense output.
    EXPECT_LT((r->at_end - reference.at_end).cwiseAbs().maxCoeff(), kDenseErrorPerTol * kTol * (1.0 + scale));
  }
  EXPECT_EQ(full.rhs_evals, 5 * full.attempts + full.accepted);
  EXPECT_EQ(half.rhs_evals, 5 * half.attempts + half.accepted);
  EXPECT_EQ(fd.rhs_evals, 5 * fd.attempts + (1 + 4 + 2) * fd.accepted);
}

// Why odeint's rosenbrock4 went: on the same Prothero-Robinson problem its
// steps grow like a first-order method's (its d4 has the wrong sign; with it
// corrected, RODAS still loses order there). If a future Boost fixes both,
// this test fails and the choice should be measured again.
TEST(Rodasp, OdeintRosenbrock4LosesOrderWhereRodaspDoesNot) {
  namespace odeint = boost::numeric::odeint;
  using V = boost::numeric::ublas::vector<double>;
  using M = boost::numeric::ublas::matrix<double>;
  auto steps_of = [](double tol) {
    auto f = [](const V& y, V& dy, double t) {
      dy[0] = kLambda * (y[0] - std::sin(kOmega * t)) + kOmega * std::cos(kOmega * t);
    };
    auto jac = [](const V&, M& J, double t, V& dfdt) {
      J(0, 0) = kLambda;
      dfdt[0] = -kLambda * kOmega * std::cos(kOmega * t) - kOmega * kOmega * std::sin(kOmega * t);
    };
    odeint::rosenbrock4_controller<odeint::rosenbrock4<double>> c(tol, tol);
    V y(1);
    y[0] = 0.0;
    double t = 0.0, dt = 1e-5;
    long steps = 0;
    while (t < 1.0) {
      dt = std::min(dt, 1.0 - t);
      if (c.try_step(std::make_pair(f, jac), y, t, dt) == odeint::success) ++steps;
    }
    return steps;
  };
  const double odeint_growth = static_cast<double>(steps_of(1e-8)) / steps_of(1e-5);
  auto exact = [](double t) { return State1(std::sin(kOmega * t)); };
  const double rodasp_growth = static_cast<double>(integrate(ProtheroRobinson{}, State1(0.0), 1e-8, 1.0, exact).steps) /
                               integrate(ProtheroRobinson{}, State1(0.0), 1e-5, 1.0, exact).steps;
  EXPECT_GT(odeint_growth, kOrderFourStepGrowth);
  EXPECT_LT(rodasp_growth, odeint_growth / 1.5);
}

// The penalty method on the stiff integrator through the paper scene's first
// contacts (touchdown 1.1129 s, a graze at 1.1141 s whose force the loose
// tolerances cannot resolve) at both ends of the tolerance range: no stall,
// and the same orbit as the explicit integrator at a tight tolerance.
TEST(Rodasp, PenaltyRunsAtEveryToleranceThroughTheFirstContacts) {
  core::Scene base = test::paper_scene();
  base.end_time_s = 1.3;
  const test::Run ref =
      test::run(test::with_method(base, test::Solver{core::Method::kPenalty, core::Integrator::kDopri5}, 1e-9, 1e-12));
  ASSERT_FALSE(ref.result.failure.has_value());
  ASSERT_FALSE(ref.out.events.empty());
  for (double rtol : {1e-3, 1e-6, 1e-10}) {
    core::Scene s = test::with_method(base, test::Solver{core::Method::kPenalty, core::Integrator::kRosenbrock4}, rtol,
                                      rtol * 1e-3);
    // A stall shows as a spent budget, not as a long wait: the runs take
    // 1e3 (rtol 1e-3) to 2e5 (1e-10) steps here.
    s.solver.max_steps = 1'000'000;
    s.solver.max_wall_time_s = 20.0;
    const test::Run r = test::run(s);
    ASSERT_FALSE(r.result.failure.has_value()) << "rtol " << rtol << ": " << r.result.failure->message;
    ASSERT_EQ(r.out.samples.size(), ref.out.samples.size());
    double max_dr = 0.0;
    for (size_t i = 0; i < r.out.samples.size(); ++i)
      max_dr = std::max(max_dr, (r.out.samples[i].kin.rotor_pos - ref.out.samples[i].kin.rotor_pos).norm());
    if (rtol < 1e-3) {
      // Against dopri5 at rtol 1e-9, itself ~1e-10 m off (its error at rtol
      // 1e-9 in rotor_rub_bench is below 2e-9 m from its own k_c limit):
      // 50 rtol of the orbit (2e-3 m) but no tighter than 1e-9 m, the
      // reference's own uncertainty.
      EXPECT_LT(max_dr, std::max(50.0 * rtol * 2e-3, 1e-9)) << "rtol " << rtol;
      // The contacts are the reference's: the first touchdown within 1e-6 s.
      ASSERT_FALSE(r.out.events.empty());
      EXPECT_NEAR(r.out.events.front().t_s, ref.out.events.front().t_s, 1e-6) << "rtol " << rtol;
      // Restarts only at the law's edges: no fallback chain (each event
      // once, where the reference has as many).
      EXPECT_LE(r.result.stats.restarts, 4 * static_cast<long>(ref.out.events.size()) + 4) << "rtol " << rtol;
    } else {
      // At rtol 1e-3 the position error allowed per step (3e-6 m) is about
      // 400 times the contact's penetration (8e-9 m): the graze at 1.1141 s
      // is not resolved and the orbit's phase drifts. The claim there is
      // that the run finishes, within a budget, and stays in the bore's
      // neighbourhood (the clearance is 2e-3 m).
      EXPECT_LT(max_dr, 1e-3) << "rtol " << rtol;
    }
  }
}

}  // namespace
}  // namespace rotor_rub
