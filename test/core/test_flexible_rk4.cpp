// Classic RK4 on the penalty contact of a flexible rotor: its stability
// bound from the eigenvalues of the rotor linearised in sustained contact
// (rk4_stability.hpp) against RK4's region and against the Jeffcott's
// closed form, and runs below and above it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <memory>
#include <string>

#include "integrators/rk4_stability.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/contact_method.hpp"
#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

double rk4_gain(std::complex<double> z) {
  return std::abs(1.0 + z + z * z / 2.0 + z * z * z / 6.0 + z * z * z * z / 24.0);
}

// |R| = 1 within rounding counts as inside (rk4_stability.cpp).
constexpr double kRounding = 1e-12;

}  // namespace

// The bound is the first exit of the ray s lambda from RK4's region, for
// any |lambda|: the ray inside up to it and outside just past it. On the
// negative real axis it is the real root of x^3 - 4 x^2 + 12 x - 24 = 0
// (|R(-x)| = 1 leaves that cubic), 2.7853; on the imaginary axis |R(iy)|^2
// = 1 - y^6 / 72 + y^8 / 576, so 2 sqrt(2); between the axes it falls to
// 2.616 (at 122 degrees), so the real axis's 2.785 is no bound for every
// damping ratio. The edge is found where |R| = 1 + kRounding: on the real
// axis (|dR/dx| = 1.5) 6.7e-13 past the root, which moves the cubic (slope
// 13) by 8.7e-12.
TEST(Rk4Stability, TheBoundIsTheEdgeOfRk4sRegionOnEveryRay) {
  const double real_axis = core::rk4_stable_step_s({-1.0, 0.0});
  EXPECT_NEAR(real_axis * real_axis * real_axis - 4.0 * real_axis * real_axis + 12.0 * real_axis - 24.0, 0.0, 1e-11);
  EXPECT_NEAR(real_axis, 2.785, 1e-3);
  EXPECT_NEAR(core::rk4_stable_step_s({0.0, 1.0}), 2.0 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(core::rk4_stable_step_s({0.0, -50.0}), 2.0 * std::sqrt(2.0) / 50.0, 1e-12);
  EXPECT_TRUE(std::isinf(core::rk4_stable_step_s({0.0, 0.0})));
  double narrowest = 3.0;
  for (int degrees = 91; degrees < 270; degrees += 2) {
    const std::complex<double> lambda = 3.0e4 * std::polar(1.0, degrees * M_PI / 180.0);
    const double h = core::rk4_stable_step_s(lambda);
    narrowest = std::min(narrowest, h * std::abs(lambda));
    for (int i = 1; i < 200; ++i) EXPECT_LE(rk4_gain(i / 200.0 * h * lambda), 1.0) << degrees;
    EXPECT_LE(rk4_gain(h * lambda), 1.0 + 2.0 * kRounding) << degrees;  // the edge, and h lambda's rounding
    EXPECT_GT(rk4_gain(1.001 * h * lambda), 1.0) << degrees;
  }
  EXPECT_NEAR(narrowest, 2.616, 0.005);
}

namespace {

// The paper's Jeffcott as a one-node rotor file (test_flexible_rotor_runs.cpp).
core::Scene jeffcott_file_scene() {
  core::Scene s = test::paper_scene();
  s.rotor.file = test::source_path("test/data/rotors/jeffcott_matrices.yaml");
  s.rotor.planar_modes = 1;
  s.solver.method = core::Method::kPenalty;
  s.solver.integrator = core::Integrator::kRk4;
  return s;
}

double flexible_bound_s(const core::Scene& s) {
  return core::flexible_rk4_stable_step_s(core::load_flexible_rotor(s.rotor), s.model, s.speed.max_speed_rad_per_s);
}

}  // namespace

// On the Jeffcott's one-node file the fastest eigenvalues are the
// Jeffcott's contact mode's, and under a motor the spin's lever and inertia
// are the Jeffcott's (max h^T M^-1 h = m e^2 on this file), so the bound
// from the eigenvalues of the whole linearised rotor is the closed form's
// (rk4_stability.hpp) to what that form leaves out: the rotor's and
// stator's own springs and dampers, k_s / k_c = 3.8e-5 (3.1e-5 measured).
// Beyond the paper's scene: restitution 0.5 (an underdamped contact mode,
// off the real axis), friction 0.5, a rigid stator, the motor drive.
TEST(FlexibleRk4, TheJeffcottsFileHasTheJeffcottsBound) {
  for (const bool rigid : {false, true}) {
    for (const double restitution : {0.0, 0.5}) {
      for (const double friction : {0.0, 0.5}) {
        for (const bool motor : {false, true}) {
          core::Scene s = jeffcott_file_scene();
          if (rigid) s.model.stator_model = core::StatorModel::kRigid;
          s.model.restitution = restitution;
          s.model.friction_coefficient = friction;
          if (motor) s.model.drive_model = core::DriveModel::kMotor;
          core::Scene jeffcott = s;
          jeffcott.rotor.file.clear();
          const double closed_form = core::rk4_stable_step_s(core::JeffcottModel(jeffcott.model));
          const double ratio = flexible_bound_s(s) / closed_form;
          SCOPED_TRACE(testing::Message() << "rigid " << rigid << " e " << restitution << " f " << friction << " motor "
                                          << motor << ": ratio " << ratio);
          EXPECT_NEAR(ratio, 1.0, 1e-4);
        }
      }
    }
  }
}

namespace {

// The seal-rub example (config/seal_rub_runup.yaml, 8 planar modes, a rigid
// seal, k_c 1e9 N/m) on the penalty method and rk4, cut after the first
// contact (1.24 s) and into the sustained rub (from 1.37 s).
core::Scene seal_rub_rk4(double step_s) {
  core::Scene s = core::load_scene(test::source_path("config/seal_rub_runup.yaml"));
  s.solver.method = core::Method::kPenalty;
  s.solver.integrator = core::Integrator::kRk4;
  s.solver.fixed_step_s = step_s;
  s.end_time_s = 1.6;
  return s;
}

std::string failure_of(const test::Run& r) { return r.result.failure ? r.result.failure->message : ""; }

}  // namespace

namespace {

// The method alone (validate_scene would refuse the step) to the scene's
// end: its events.
std::size_t events_alone_to_the_end(const core::Scene& s) {
  const std::unique_ptr<core::ContactMethod> method = core::make_contact_method(s);
  const core::SpeedProfile profile(s.speed);
  method->start(0.0, core::JeffcottModel(s.model).initial_kinematics(profile.at(0.0)), profile.segment_at(0.0));
  std::vector<core::ContactEvent> events;
  while (method->step_end() < s.end_time_s) method->step(s.end_time_s, events);
  return events.size();
}

}  // namespace

// The scene's validation holds the step to the bound, naming the key. Just
// above it (1.2x) the clamp keeps the state bounded but the contact
// chatters: to 1.6 s, 19 822 events against 101 at 0.9x (measured); far
// above it (10x) the method diverges and says so (in free flight, before
// the first contact at 1.24 s: the highest of the 8 planar modes of both
// planes' shapes lie above a tenth of the contact mode's frequency).
TEST(FlexibleRk4, RefusedAboveTheBoundChattersAndDivergesFarAbove) {
  const double h_max = flexible_bound_s(seal_rub_rk4(1e-6));
  EXPECT_NO_THROW(core::validate_scene(seal_rub_rk4(0.99 * h_max)));
  try {
    core::validate_scene(seal_rub_rk4(1.01 * h_max));
    ADD_FAILURE() << "accepted a step above RK4's bound";
  } catch (const core::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("scene key 'fixed_step_s'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("RK4's stability bound"), std::string::npos) << e.what();
  }
  const std::size_t below = events_alone_to_the_end(seal_rub_rk4(0.9 * h_max));
  const std::size_t chatter = events_alone_to_the_end(seal_rub_rk4(1.2 * h_max));
  std::printf("0.9x: %zu events; 1.2x: %zu events\n", below, chatter);
  EXPECT_GT(chatter, 10 * below);
  const auto above = test::run_method_alone(seal_rub_rk4(10.0 * h_max));
  ASSERT_TRUE(above.has_value());
  EXPECT_EQ(above->failure_class, core::FailureClass::kDiverged);
  EXPECT_NE(above->message.find("unstable"), std::string::npos) << above->message;
  EXPECT_LT(above->time_s, 1.24);
}

// Below the bound RK4 converges to the other integrators' run of the same
// law: at a quarter of it (5.5e-6 s) within 1e-11 m of rosenbrock4 at rtol
// 1e-9 (4.8e-12 m measured), and it keeps the
// method's promises: the same events at any output rate, bit for bit, and
// the same run twice.
TEST(FlexibleRk4, BelowTheBoundItRunsThePenaltyLawsRun) {
  const double h = flexible_bound_s(seal_rub_rk4(1e-6)) / 4.0;
  const test::Run rk4 = test::run(seal_rub_rk4(h));
  ASSERT_FALSE(rk4.result.failure) << failure_of(rk4);
  core::Scene reference_scene = seal_rub_rk4(h);
  reference_scene.solver.integrator = core::Integrator::kRosenbrock4;
  reference_scene.solver.rtol = 1e-9;
  reference_scene.solver.atol = 1e-12;
  const test::Run reference = test::run(reference_scene);
  ASSERT_FALSE(reference.result.failure) << failure_of(reference);
  ASSERT_EQ(rk4.out.samples.size(), reference.out.samples.size());
  ASSERT_FALSE(rk4.out.events.empty());
  EXPECT_EQ(rk4.out.events.size(), reference.out.events.size());
  double worst_m = 0.0;
  for (std::size_t i = 0; i < rk4.out.samples.size(); ++i) {
    worst_m = std::max(
        worst_m, (rk4.out.samples[i].kin.rotor_pos - reference.out.samples[i].kin.rotor_pos).cwiseAbs().maxCoeff());
  }
  std::printf("rk4 at h = %.3g s against rosenbrock4: %.3g m\n", h, worst_m);
  EXPECT_LT(worst_m, 1e-11);
  EXPECT_TRUE(rk4.out.samples.back().in_contact);

  core::Scene faster_output = seal_rub_rk4(h);
  faster_output.output_rate_hz = 7300.0;
  const test::Run other_rate = test::run(faster_output);
  ASSERT_EQ(other_rate.out.events.size(), rk4.out.events.size());
  for (std::size_t i = 0; i < rk4.out.events.size(); ++i) {
    EXPECT_EQ(other_rate.out.events[i].t_s, rk4.out.events[i].t_s) << i;
    EXPECT_EQ(other_rate.out.events[i].kind, rk4.out.events[i].kind) << i;
  }
  const test::Run again = test::run(seal_rub_rk4(h));
  ASSERT_EQ(again.out.samples.size(), rk4.out.samples.size());
  for (std::size_t i = 0; i < rk4.out.samples.size(); ++i) {
    EXPECT_EQ(again.out.samples[i].kin.rotor_pos, rk4.out.samples[i].kin.rotor_pos) << i;
  }
}

// Under a motor the speed controller is part of the system: in the torque
// limit its anti-windup's integral decays at -K_i / K_p, which a small K_p
// makes the fastest eigenvalue (2.5e6 1/s at K_p 1e-6, K_i 2.5, against
// the contact's 5.7e5 1/s here), on the real axis.
TEST(FlexibleRk4, ASlowSpeedControllersAntiWindupBoundsTheStep) {
  core::Scene s = jeffcott_file_scene();
  s.model.drive_model = core::DriveModel::kMotor;
  s.model.drive_proportional_gain_N_m_s_per_rad = 1e-6;
  const double expected_s =
      core::rk4_stable_step_s(-s.model.drive_integral_gain_N_m_per_rad / s.model.drive_proportional_gain_N_m_s_per_rad);
  EXPECT_NEAR(expected_s, 2.7853 / 2.5e6, 1e-4 * expected_s);
  EXPECT_DOUBLE_EQ(flexible_bound_s(s), expected_s);
  core::Scene jeffcott = s;
  jeffcott.rotor.file.clear();
  EXPECT_DOUBLE_EQ(core::rk4_stable_step_s(core::JeffcottModel(jeffcott.model)), expected_s);
}
