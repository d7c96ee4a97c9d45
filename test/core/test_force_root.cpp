// The iteration method's force roots (ForceRoot, methods/contact_force_solver.hpp):
// TOMS 748 on a bracket grown from the last root, to rtol of the root's scale,
// and a bracket within the residual's resolution (the rounding of the
// accelerations over their slope) accepted once the budget is spent.
#include <gtest/gtest.h>

#include <cmath>

#include "methods/contact_force_solver.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

// A linear residual with its root at 1e-7 N and a rounding step there, a
// budget of two evaluations and a tolerance of 1e-12 of a 1e-5 N scale: two
// TOMS 748 steps leave a wider bracket. Without a resolution that is a
// failure (kNotConverged); with one wider than what is left it is the root,
// inside the first bracket [0, 3] N (the warm start 1 N and its step 2 N).
TEST(ForceRoot, ABracketWithinTheResolutionIsARootOnceTheBudgetIsSpent) {
  constexpr double kRoot_N = 1e-7, kScale_N = 1e-5;
  auto r = [](double f) { return 2.4 * (f - kRoot_N) + (f > kRoot_N ? 3e-15 : -2e-18); };
  long iterations = 0;
  const core::ForceRoot strict(1e-12, 2, "normal force");
  try {
    strict.solve(r, 0.0, r(0.0), 1.0, iterations, kScale_N, 0.0);
    FAIL() << "converged within two evaluations: the case no longer tests the budget";
  } catch (const core::MethodFailure& e) {
    EXPECT_EQ(e.failure_class, core::FailureClass::kNotConverged);
  }
  const core::ForceRoot resolved(1e-12, 2, "normal force");
  const double f = resolved.solve(r, 0.0, r(0.0), 1.0, iterations, kScale_N, 10.0);
  EXPECT_GE(f, 0.0);
  EXPECT_LE(f, 3.0);
}

// The transitions sweep's iteration rows at rtol 1e-3 with the default atol
// (docs/numerics.md, "Loose tolerances"): at 5.36 s the normal force's
// bracket was 1.3 times its tolerance wide after the 100 evaluations of the
// default budget, its residual there only its rounding (-2e-18 and 3.6e-15
// m/s^2 at its ends), and the run ended in not_converged. It runs through.
TEST(ForceRoot, TheDryWhirlAtALooseToleranceRunsThrough) {
  core::Scene s = core::load_scene(test::source_path("config/dry_whirl_rundown.yaml"));
  s = test::with_method(s, test::Solver{core::Method::kIteration, core::Integrator::kDop853}, 1e-3, 1e-9);
  core::set_scene_value(s, "friction_coefficient", "0.1");
  core::set_scene_value(s, "acceleration_rad_per_s2", "50");
  s.end_time_s = 11.1;
  const test::Run r = test::run(s);
  ASSERT_FALSE(r.result.failure.has_value()) << r.result.failure->message;
}

}  // namespace
