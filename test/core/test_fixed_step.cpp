// The fixed-step RK4 integrator on the penalty contact: stable below the
// theoretical step bound h_max = r / omega_c, diverged (and reported as
// such, with the samples before) above it; rigid methods refuse it.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "integrators/rk4_stability.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

// RK4's stability interval on the negative real axis, [-2.7853, 0] (the real
// root of x^3 - 4 x^2 + 12 x - 24, test_flexible_rk4.cpp): for e = 0
// the penalty damper is overdamped (zeta = 4.81, the restitution floor 0.01,
// contact_law.hpp), so the contact mode's eigenvalues are real,
// -omega_c (zeta +- sqrt(zeta^2 - 1)), and the fast one bounds the step.
constexpr double kRk4RealAxisRadius = 2.7852935634;
// The bound is derived for the contact mode alone (k_c >> k_r, k_s: 1e9
// against 2.5e3 and 3.8e4 N/m here) and ignores friction coupling; 20 %
// either side of it is where the test expects the clear verdicts.
constexpr double kMarginBelow = 0.8, kMarginAbove = 1.5, kDivergedMultiple = 5.0;

struct Count : core::SimulationObserver {
  long samples = 0;
  double first_touchdown_s = -1.0;
  void on_sample(const core::Sample& s) override {
    ++samples;
    EXPECT_TRUE(s.kin.rotor_pos.allFinite());
  }
  void on_event(const core::ContactEvent& e) override {
    if (e.kind == core::EventKind::kTouchdown && first_touchdown_s < 0.0) first_touchdown_s = e.t_s;
  }
};

core::Scene rk4_scene(double h_s) {
  core::Scene s = test::paper_scene();
  s.solver.method = core::Method::kPenalty;
  s.solver.integrator = core::Integrator::kRk4;
  s.solver.fixed_step_s = h_s;
  s.end_time_s = 1.5;  // sustained contact from 1.11 s
  return s;
}

double theoretical_h_max_s(const core::Scene& s) {
  const core::JeffcottModel m(s.model);
  const double zeta = core::contact_damping_ratio(s.model);
  EXPECT_GT(zeta, 1.0);
  const double fast = zeta + std::sqrt(zeta * zeta - 1.0);
  return kRk4RealAxisRadius / (fast * std::sqrt(s.model.contact_stiffness_N_per_m / m.effective_mass_kg()));
}

}  // namespace

TEST(FixedStep, StableBelowTheBoundDivergedAbove) {
  const double h_max = theoretical_h_max_s(rk4_scene(1e-6));
  EXPECT_NEAR(h_max, 4.91e-6, 0.01e-6);  // k_c 1e9, m_eff 0.281 kg, zeta 4.81
  // (to the constant's 11 digits)
  EXPECT_NEAR(h_max, core::rk4_stable_step_s(core::JeffcottModel(rk4_scene(1e-6).model)), 1e-10 * h_max);

  Count below_samples;
  const core::RunResult below = core::run_scene(rk4_scene(kMarginBelow * h_max), below_samples);
  EXPECT_FALSE(below.failure) << below.failure->message;
  EXPECT_EQ(below_samples.samples, 1501);
  EXPECT_GT(below.stats.touchdowns, 0);
  // The touchdown is located on the dense output and restarted at (a fixed
  // step then ends there): at the reference's first contact, 1e-9 s (RK4's
  // error at 4e-6 s steps, h^4 ~ 3e-22 per unit time, is far below the
  // location's resolution).
  test::Collect reference;
  core::run_scene(test::with_method(test::paper_scene(), test::Solver{}, 1e-12, 1e-15), reference);
  ASSERT_FALSE(reference.events.empty());
  EXPECT_NEAR(below_samples.first_touchdown_s, reference.events.front().t_s, 1e-9);

  // Above the bound the clamp keeps the state bounded for a while (to ~4x,
  // measured) but the contact chatters: validate_scene() refuses the step.
  core::Scene above_scene = rk4_scene(kMarginAbove * h_max);
  EXPECT_THROW(core::validate_scene(above_scene), core::SceneError);
  core::validate_scene(rk4_scene(kMarginBelow * h_max));  // accepted
  // Far above (5x, measured) it diverges, reported as such, in contact after
  // the first touch (the method alone: Simulation refuses the scene).
  EXPECT_THROW(core::Simulation{rk4_scene(kDivergedMultiple * h_max)}, core::SceneError);
  const auto above = test::run_method_alone(rk4_scene(kDivergedMultiple * h_max));
  ASSERT_TRUE(above.has_value());
  EXPECT_EQ(above->failure_class, core::FailureClass::kDiverged);
  EXPECT_NE(above->message.find("unstable"), std::string::npos) << above->message;
  EXPECT_GT(above->time_s, 1.11);
  EXPECT_LT(above->time_s, 1.5);
}

TEST(FixedStep, Rk4IsForThePenaltyMethodOnly) {
  try {
    core::scene_from_values({{"method", "switching"}, {"integrator", "rk4"}});
    FAIL() << "accepted rk4 with switching";
  } catch (const core::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("accepted with method 'penalty' only"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(core::scene_from_values({{"method", "penalty"}, {"integrator", "rk4"}, {"fixed_step_s", "1e-6"}}));
}

// An underdamped contact mode (restitution 0.226: zeta 0.656, its
// eigenvalues at 131 degrees) leaves RK4's region before the real axis's
// radius: the bound follows its ray, 2.66 / omega_c, 4.5 % inside
// 2.785 / omega_c, where |R(h lambda)| exceeds 1 (rk4_stability.hpp).
TEST(FixedStep, AnUnderdampedContactModeIsBoundAlongItsRay) {
  core::Scene s = rk4_scene(1e-6);
  s.model.friction_coefficient = 0.0;  // the tangential damper's real eigenvalue would bound it first
  s.model.restitution = 0.226;
  const core::JeffcottModel m(s.model);
  const double zeta = core::contact_damping_ratio(s.model);
  EXPECT_NEAR(zeta, 0.656, 1e-3);
  const double omega_c = std::sqrt(s.model.contact_stiffness_N_per_m / m.effective_mass_kg());
  const std::complex<double> lambda = omega_c * std::complex<double>(-zeta, std::sqrt(1.0 - zeta * zeta));
  auto gain = [](std::complex<double> z) {
    return std::abs(1.0 + z + z * z / 2.0 + z * z * z / 6.0 + z * z * z * z / 24.0);
  };
  const double h_max = core::rk4_stable_step_s(m);
  EXPECT_NEAR(h_max * omega_c, 2.66, 0.005);
  EXPECT_LE(gain(h_max * lambda), 1.0 + 2e-12);
  EXPECT_GT(gain(kRk4RealAxisRadius / omega_c * lambda), 1.0 + 1e-3);
  s.solver.fixed_step_s = 1.01 * h_max;
  EXPECT_THROW(core::validate_scene(s), core::SceneError);
}
