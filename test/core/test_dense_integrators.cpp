// Every dense integrator of the methods (dense_dopri5, dense_high_order's
// rkf78 and dop853, dense_rodasp, dense_rk4) through one typed suite, as
// odeint tests its steppers and Drake its integrators: one step from the
// exact state of a forced oscillator, h and h / 2, and the local errors'
// ratio gives the order of the step and of the dense output inside it. A
// wrong coefficient, stage time or interpolation weight drops an order.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "integrators/dense_dopri5.hpp"
#include "integrators/dense_high_order.hpp"
#include "integrators/dense_rk4.hpp"
#include "integrators/dense_rodasp.hpp"
#include "integrators/dense_stiffness_switch.hpp"
#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub {
namespace {

using State = Eigen::Vector2d;

// x'' + x = cos(2 t), from rest at t = 0: x = (cos t - cos 2t) / 3
// (non-autonomous, so the stage times count).
struct Forced {
  // RODASP differences the Jacobian (dense_rodasp.hpp's hooks off).
  static constexpr bool kAnalyticJacobian = false, kSecondOrderJacobian = false, kOwnErrorNorm = false;
  void operator()(const State& x, State& dx, double t) const {
    dx[0] = x[1];
    dx[1] = -x[0] + std::cos(2.0 * t);
  }
  // The Hermite dense output's x'' in closed form (else a central difference,
  // whose rounding would floor the errors measured here).
  static constexpr bool kOwnEndDerivatives = true;
  int end_derivatives(const State& x, double t, core::StepEnd /*end*/, State& dx, State& ddx) const {
    (*this)(x, dx, t);
    ddx[0] = dx[1];
    ddx[1] = -dx[0] - 2.0 * std::sin(2.0 * t);
    return 1;
  }
  static State exact(double t) {
    return {(std::cos(t) - std::cos(2.0 * t)) / 3.0, (-std::sin(t) + 2.0 * std::sin(2.0 * t)) / 3.0};
  }
};

// The oscillator as a mechanical layout (position, velocity): the Hermite
// dense output of the high-order integrators interpolates it as such.
struct OscillatorLayout {
  static constexpr int kDof = 1;
  static constexpr int kSpinSize = 0;
  static constexpr int kSize = 2;
  static constexpr int kModal = kSize;
  using State = Eigen::Vector2d;
};

// Tolerances so loose that the first attempt of h is accepted: one step of h.
constexpr double kLooseTol = 1e3;
constexpr long kMaxSteps = 10;

// The local error's order is the method's order + 1 (one step's error is
// O(h^(p+1))); so is the dense output's. Measured orders sit within a few
// tenths of the theory at these h (the next term of the error expansion);
// 0.45 fails a drop by one order.
constexpr double kOrderTol = 0.45;

struct Dopri5Case {
  static constexpr bool kAdaptive = true;
  static constexpr const char* kName = "dopri5";
  static constexpr double kStepOrder = 5, kDenseOrder = 4;  // its own dense output is of order 4
  static core::DenseDopri5<State> make(double) { return {kLooseTol, kLooseTol, 0.0, kMaxSteps}; }
};
struct Rkf78Case {
  static constexpr bool kAdaptive = true;
  static constexpr const char* kName = "rkf78";
  // odeint's Fehlberg 7(8) propagates the 8th-order solution. The dense
  // output (dense_high_order.hpp): each position the degree-7 Hermite
  // polynomial of the ends' q, v, a, j (local error h^8), its velocity that
  // polynomial's derivative (h^7): order 6.
  static constexpr double kStepOrder = 8, kDenseOrder = 6;
  static core::DenseRkf78<OscillatorLayout> make(double) { return {kLooseTol, kLooseTol, 0.0, kMaxSteps}; }
};
struct Dop853Case {
  static constexpr bool kAdaptive = true;
  static constexpr const char* kName = "dop853";
  static constexpr double kStepOrder = 8, kDenseOrder = 6;  // the same Hermite output as rkf78's
  static core::DenseDop853<OscillatorLayout> make(double) { return {kLooseTol, kLooseTol, 0.0, kMaxSteps}; }
};
struct Dop853Rosenbrock4Case {
  static constexpr bool kAdaptive = true;
  static constexpr const char* kName = "dop853_rosenbrock4";
  // dop853 until its steps are bound by stability (test_stiffness_switch.cpp): one step is dop853's.
  static constexpr double kStepOrder = 8, kDenseOrder = 6;
  static core::DenseStiffnessSwitch<OscillatorLayout> make(double) { return {kLooseTol, kLooseTol, 0.0, kMaxSteps}; }
};
struct RodaspCase {
  static constexpr bool kAdaptive = true;
  static constexpr const char* kName = "rosenbrock4";
  // RODASP: order 4; its continuous extension is of order 3.
  static constexpr double kStepOrder = 4, kDenseOrder = 3;
  static core::DenseRodasp<State> make(double) { return {kLooseTol, kLooseTol, 0.0, kMaxSteps}; }
};
struct Rk4Case {
  static constexpr bool kAdaptive = false;
  static constexpr const char* kName = "rk4";
  // Classic RK4; the cubic Hermite between its ends is of order 3.
  static constexpr double kStepOrder = 4, kDenseOrder = 3;
  static core::DenseRk4<State> make(double h_s) { return {h_s, kMaxSteps}; }
};

template <class Case>
class DenseIntegrator : public ::testing::Test {
 protected:
  // One step of h from the exact state at several t0 (so that no error
  // constant that happens to vanish at one t0 hides the order): the largest
  // error at a step's end and of the dense output inside a step.
  struct LocalErrors {
    double step = 0.0, dense = 0.0;
  };
  static LocalErrors one_step(double h) {
    LocalErrors e;
    for (const double t0 : {0.3, 1.1, 2.3, 4.0}) {
      auto integ = Case::make(h);
      core::RunStats stats;
      Forced sys;
      integ.initialize(sys, Forced::exact(t0), t0, h, stats);
      integ.do_step(sys, stats);
      EXPECT_DOUBLE_EQ(integ.t_new(), t0 + h) << Case::kName << ": the step was not h";
      State x;
      integ.state_at(integ.t_new(), x);
      e.step = std::max(e.step, (x - Forced::exact(integ.t_new())).cwiseAbs().maxCoeff());
      for (double s : {0.2, 0.35, 0.5, 0.65, 0.8}) {
        const double t = t0 + s * h;
        integ.state_at(t, x);
        e.dense = std::max(e.dense, (x - Forced::exact(t)).cwiseAbs().maxCoeff());
      }
    }
    return e;
  }
};

using Integrators = ::testing::Types<Dopri5Case, Rkf78Case, Dop853Case, Dop853Rosenbrock4Case, RodaspCase, Rk4Case>;
class IntegratorNames {
 public:
  template <class T>
  static std::string GetName(int) {
    return T::kName;
  }
};
TYPED_TEST_SUITE(DenseIntegrator, Integrators, IntegratorNames);

template <class... Case>
std::set<std::string> case_names(::testing::Types<Case...>) {
  return {Case::kName...};
}

// The suite has a case for every concrete integrator (the step and dense
// orders of each) and for nothing else: a new integrator fails here until
// its case is in Integrators. (rosenbrock4's case is RODASP, which that name
// runs.)
TEST(DenseIntegratorSuite, HasACaseForEveryIntegrator) {
  const std::set<std::string> covered = case_names(Integrators{});
  std::set<std::string> integrators;
  for (const core::Integrator i : core::kAllIntegrators) {
    if (i != core::Integrator::kAuto) integrators.insert(core::to_string(i));
  }
  EXPECT_EQ(covered, integrators);
}

TYPED_TEST(DenseIntegrator, StepAndDenseOutputConvergeWithTheirOrders) {
  // h = 0.3 and 0.15 (the period is 2 pi): in the asymptotic range of every
  // integrator here (measured orders within 0.31 of the theory from h = 0.2
  // to 0.6), and above the rounding floor at h / 2 (dop853's and rkf78's
  // step errors are 1e-13 and 5e-14 there).
  const double h = 0.3;
  const auto coarse = TestFixture::one_step(h);
  const auto fine = TestFixture::one_step(h / 2);
  ASSERT_GT(fine.step, 1e-14) << "at the rounding floor: take a larger h";
  const double step_order = std::log2(coarse.step / fine.step) - 1.0;
  const double dense_order = std::log2(coarse.dense / fine.dense) - 1.0;
  EXPECT_NEAR(step_order, TypeParam::kStepOrder, kOrderTol) << coarse.step << " " << fine.step;
  EXPECT_NEAR(dense_order, TypeParam::kDenseOrder, kOrderTol) << coarse.dense << " " << fine.dense;
}

// Before its first step an integrator's interval is one instant: the dense
// output there is the initial state itself (a method samples its start
// before it steps, and a restart at an event samples it again).
TYPED_TEST(DenseIntegrator, BeforeItsFirstStepItAnswersTheInitialState) {
  const double t0 = 1.1;
  auto integ = TypeParam::make(0.3);
  core::RunStats stats;
  Forced sys;
  integ.initialize(sys, Forced::exact(t0), t0, 0.3, stats);
  State x;
  integ.state_at(t0, x);
  EXPECT_EQ(x, Forced::exact(t0)) << TypeParam::kName;
}

// x'' = -w^2 x with w = 1e60: a first step of 1e-3 s (w h = 1e57) overflows
// in an explicit scheme's stages. Each adaptive integrator rejects the
// non-finite trial and cuts the step until one ends finite (a long step
// carried over from another integrator: step_ends.hpp). A right-hand side
// that is never finite is a divergence once the cuts reach min_step_s. RK4's
// fixed step has nothing to cut (test_fixed_step).
constexpr double kAcceptedStepTolerance = 1e-4;
struct Stiff {
  static constexpr bool kAnalyticJacobian = false, kSecondOrderJacobian = false, kOwnErrorNorm = false;
  static constexpr bool kOwnEndDerivatives = false;
  static constexpr double kOmega = 1e60;
  bool poisoned = false;  // the right-hand side NaN everywhere
  void operator()(const State& x, State& dx, double) const {
    dx[0] = poisoned ? std::nan("") : x[1];
    dx[1] = -kOmega * kOmega * x[0];
  }
};

TYPED_TEST(DenseIntegrator, ANonFiniteTrialIsRejectedAndTheStepCut) {
  if constexpr (!TypeParam::kAdaptive) {
    GTEST_SKIP() << "a fixed step";
  } else {
    using Integ = decltype(TypeParam::make(0.0));
    // rtol 1e-6, min_step_s 1e-300, a budget far beyond the ~90 cuts from 1e-3 s to w h ~ 1.
    Integ integ(1e-12, 1e-6, 1e-300, 100000);
    core::RunStats stats;
    Stiff sys;
    integ.initialize(sys, State(1.0, 0.0), 0.0, 1e-3, stats);
    ASSERT_NO_THROW(integ.do_step(sys, stats)) << TypeParam::kName;
    EXPECT_GT(integ.t_new(), 0.0);
    // The accepted step is right: x = cos(w t) to a hundred times rtol (one
    // step's error is within the tolerance, up to the controller's safety).
    EXPECT_NEAR(integ.x_new()[0], std::cos(Stiff::kOmega * integ.t_new()), kAcceptedStepTolerance) << TypeParam::kName;
    EXPECT_GT(stats.rejected_steps, 0) << TypeParam::kName;

    Integ poisoned_integ(1e-12, 1e-6, 1e-12, 100000);
    Stiff poisoned;
    core::RunStats poisoned_stats;
    poisoned_integ.initialize(poisoned, State(1.0, 0.0), 0.0, 1e-3, poisoned_stats);
    poisoned.poisoned = true;
    try {
      poisoned_integ.do_step(poisoned, poisoned_stats);
      ADD_FAILURE() << TypeParam::kName << ": a NaN right-hand side stepped";
    } catch (const core::MethodFailure& f) {
      EXPECT_EQ(f.failure_class, core::FailureClass::kDiverged) << TypeParam::kName << ": " << f.what();
    }
  }
}

}  // namespace
}  // namespace rotor_rub
