// Dormand-Prince 8(5,3) (dop853.hpp): its tableau against the order
// conditions a transcription error would break, its order measured on
// closed forms (a nonlinear autonomous problem and a forced oscillator), its
// error control on a pure quadrature (where Fehlberg's 7(8) estimate is
// blind), and its Hermite dense output (dense_high_order.hpp) between the steps.
// The contact physics on dop853 is in the shared suites (test_support.hpp's
// rigid_solvers()).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "integrators/dense_high_order.hpp"
#include "integrators/dop853.hpp"
#include "rotor_rub_sim/core/model.hpp"

namespace rotor_rub {
namespace {

using core::Dop853;
using core::Dop853Tableau;
using T = Dop853Tableau;

// The coefficients are given to 30 digits; in double each carries a
// relative rounding of 1.1e-16, and the largest is 43.5 in magnitude: a sum
// of ~10 of them is exact to ~1e-14. A wrong digit among the first ~12 of
// a coefficient of order 1 or more moves a sum by more than that (a small
// one's, or an error weight's, shows in the measured order instead).
constexpr double kTableauTol = 2e-14;

TEST(Dop853Tableau, RowSumsAreTheNodes) {
  const double c[] = {0, 0, T::c2, T::c3, T::c4, T::c5, T::c6, T::c7, T::c8, T::c9, T::c10, T::c11, 1.0};
  const double rows[][2] = {
      {T::a21, c[2]},
      {T::a31 + T::a32, c[3]},
      {T::a41 + T::a43, c[4]},
      {T::a51 + T::a53 + T::a54, c[5]},
      {T::a61 + T::a64 + T::a65, c[6]},
      {T::a71 + T::a74 + T::a75 + T::a76, c[7]},
      {T::a81 + T::a84 + T::a85 + T::a86 + T::a87, c[8]},
      {T::a91 + T::a94 + T::a95 + T::a96 + T::a97 + T::a98, c[9]},
      {T::a101 + T::a104 + T::a105 + T::a106 + T::a107 + T::a108 + T::a109, c[10]},
      {T::a111 + T::a114 + T::a115 + T::a116 + T::a117 + T::a118 + T::a119 + T::a1110, c[11]},
      {T::a121 + T::a124 + T::a125 + T::a126 + T::a127 + T::a128 + T::a129 + T::a1210 + T::a1211, c[12]}};
  for (const auto& r : rows) EXPECT_NEAR(r[0], r[1], kTableauTol);
}

TEST(Dop853Tableau, WeightsIntegratePolynomialsToDegreeSeven) {
  // sum_j b_j c_j^(q-1) = 1/q for q = 1..8: the quadrature conditions of
  // order 8; the embedded weights are consistent (their sums are 1 and 0).
  const double c[] = {0, T::c6, T::c7, T::c8, T::c9, T::c10, T::c11, 1.0};
  const double b[] = {T::b1, T::b6, T::b7, T::b8, T::b9, T::b10, T::b11, T::b12};
  for (int q = 1; q <= 8; ++q) {
    double sum = 0.0;
    for (int j = 0; j < 8; ++j) sum += b[j] * std::pow(c[j], q - 1);
    EXPECT_NEAR(sum, 1.0 / q, kTableauTol) << "q = " << q;
  }
  EXPECT_NEAR(T::bhh1 + T::bhh2 + T::bhh3, 1.0, kTableauTol);
  EXPECT_NEAR(T::er1 + T::er6 + T::er7 + T::er8 + T::er9 + T::er10 + T::er11 + T::er12, 0.0, kTableauTol);
}

// y' = 1 + y^2, y(0) = 0: y = tan t (nonlinear, autonomous).
using State1 = Eigen::Matrix<double, 1, 1>;
struct Riccati {
  void operator()(const State1& y, State1& dy, double /*t*/) const { dy[0] = 1.0 + y[0] * y[0]; }
};
// x'' + x = cos(2 t), x(0) = x'(0) = 0: x = (cos t - cos 2t) / 3 (forced,
// non-autonomous: the stage times matter).
using State2 = Eigen::Vector2d;
struct Forced {
  // The Hermite dense output's second derivative by central differences.
  static constexpr bool kOwnEndDerivatives = false;
  void operator()(const State2& x, State2& dx, double t) const {
    dx[0] = x[1];
    dx[1] = -x[0] + std::cos(2.0 * t);
  }
};

// Fixed steps of h to t_end (tolerances so loose every step is accepted).
template <class State, class System>
State fixed_steps(System sys, State x, double t_end, int n) {
  Dop853<State> stepper(1e3, 1e3);
  const double h = t_end / n;
  double t = 0.0;
  State dxdt, out;
  for (int i = 0; i < n; ++i) {
    sys(x, dxdt, t);
    double dt = h;
    EXPECT_TRUE(stepper.try_step(sys, x, dxdt, t, out, dt));
    x = out;
    t = (i + 1) * h;
  }
  return x;
}

TEST(Dop853, ConvergesWithOrderEight) {
  // Halving h divides the global error by 2^8 = 256: measured orders 7.89
  // (errors 1.5e-9, 6.2e-12) and 8.18 (1.7e-8, 5.9e-11), far above the
  // rounding floor (1e-15); a wrong coefficient drops the order to <= 5.
  const double e1 = std::abs(fixed_steps(Riccati{}, State1(0.0), 1.2, 12)[0] - std::tan(1.2));
  const double e2 = std::abs(fixed_steps(Riccati{}, State1(0.0), 1.2, 24)[0] - std::tan(1.2));
  const double order_riccati = std::log2(e1 / e2);
  EXPECT_GT(order_riccati, 7.5) << e1 << " " << e2;
  EXPECT_LT(order_riccati, 8.7) << e1 << " " << e2;
  auto exact = [](double t) { return (std::cos(t) - std::cos(2.0 * t)) / 3.0; };
  const double f1 = std::abs(fixed_steps(Forced{}, State2(0.0, 0.0), 10.0, 20)[0] - exact(10.0));
  const double f2 = std::abs(fixed_steps(Forced{}, State2(0.0, 0.0), 10.0, 40)[0] - exact(10.0));
  const double order_forced = std::log2(f1 / f2);
  EXPECT_GT(order_forced, 7.5) << f1 << " " << f2;
  EXPECT_LT(order_forced, 8.7) << f1 << " " << f2;
}

// y' = w cos(w t): a pure quadrature, y = sin(w t). Fehlberg's 7(8)
// estimate is identically zero here (its two solutions differ only in the
// weights of stages at equal times), so its controller grows the step
// unchecked; dop853's estimate sees the error.
struct Quadrature {
  double w;
  void operator()(const State1& /*y*/, State1& dy, double t) const { dy[0] = w * std::cos(w * t); }
};

TEST(Dop853, ControlsTheErrorOfAPureQuadrature) {
  const Quadrature sys{20.0};
  for (double tol : {1e-6, 1e-9}) {
    Dop853<State1> stepper(tol, tol);
    State1 y(0.0), dydt, out;
    double t = 0.0, dt = 1e-3, worst = 0.0;
    long steps = 0;
    while (t < 5.0) {
      sys(y, dydt, t);
      dt = std::min(dt, 5.0 - t);
      if (stepper.try_step(sys, y, dydt, t, out, dt)) {
        y = out;
        ++steps;
        worst = std::max(worst, std::abs(y[0] - std::sin(sys.w * t)));
      }
      ASSERT_LT(steps, 100000);
    }
    // The local tolerance is tol (|y| <= 1): the global error over ~16
    // periods stays within 10 tol, and the steps are not the largest
    // possible (the controller did act: > 2 steps a period).
    EXPECT_LT(worst, 10.0 * tol) << "tol " << tol;
    EXPECT_GT(steps, 2 * 16) << "tol " << tol;
  }
}

// The dense output between the steps on the forced oscillator as a
// mechanical layout (position, velocity): within the step's own error.
struct OscillatorLayout {
  static constexpr int kDof = 1;
  static constexpr int kSpinSize = 0;
  static constexpr int kSize = 2;
  static constexpr int kModal = kSize;
  using State = Eigen::Vector2d;
};

TEST(Dop853, HermiteDenseOutputMatchesTheClosedFormBetweenSteps) {
  core::DenseDop853<OscillatorLayout> integ(1e-10, 1e-10, 1e-14, 100000);
  core::RunStats stats;
  Forced sys;
  integ.initialize(sys, State2(0.0, 0.0), 0.0, 1e-3, stats);
  double worst = 0.0;
  while (integ.t_new() < 10.0) {
    integ.do_step(sys, stats);
    for (double s : {0.1, 0.37, 0.5, 0.81}) {
      const double t = integ.t_old() + s * (integ.t_new() - integ.t_old());
      State2 x;
      integ.state_at(t, x);
      worst = std::max(worst, std::abs(x[0] - (std::cos(t) - std::cos(2.0 * t)) / 3.0));
      worst = std::max(worst, std::abs(x[1] - (-std::sin(t) + 2.0 * std::sin(2.0 * t)) / 3.0));
    }
  }
  // At tol 1e-10 on an amplitude of 2/3, 50 steps of w h ~ 0.4: measured
  // 2.4e-11 at the steps' ends and 7.7e-10 between them (the velocity, the
  // degree-6 derivative of the interpolant, is the least accurate); the
  // bound leaves 2.6x for other compilers' rounding.
  EXPECT_LT(worst, 2e-9);
  EXPECT_GT(stats.steps, 10);
}

}  // namespace
}  // namespace rotor_rub
