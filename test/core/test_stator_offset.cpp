// A stator offset (a misaligned casing: the stator's rest position, scene keys
// stator_offset_x_m / _y_m) against its static closed forms, with gravity,
// in every method, elastic and rigid stators, with and without contact.
//
// Along y, stator springs pulling to d, rotor springs to 0, gravity -g:
//  * no contact: y_r = -m g / k_r, y_s = d - m_s g / k_s;
//  * resting on the bore's bottom (y_s - y_r = C, N > 0 pushing the rotor up):
//      -k_r y_r - m g + N = 0,  -k_s (y_s - d) - m_s g - N = 0
//    => y_s = (k_s d - m_s g - m g + k_r C) / (k_s + k_r), y_r = y_s - C,
//       N = k_r y_r + m g;  a rigid stator: y_s = d, y_r = d - C.
#include <gtest/gtest.h>

#include "rotor_rub_sim/core/scene_keys.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

// At rest after 20 s (the transient decays by exp(-zeta w_n 20 s) = 3e-14):
// the rigid methods hold the closed form to rounding (measured 1e-13 m and
// 5e-9 relative in N at rtol 1e-9); the penalty method's rotor sinks into the
// stator by N / k_c (3e-10 m here).
constexpr double kRestTol_m = 1e-9;
constexpr double kForceRelTol = 1e-6;
constexpr double kPenaltyForceRelTol = 1e-4;

struct Rest {
  double y_r, y_s, n;
};

Rest closed_form(const core::ModelParameters& p, double d) {
  const double g = p.gravity_m_per_s2, m = p.rotor_mass_kg, kr = p.rotor_stiffness_N_per_m;
  if (p.stator_model == core::StatorModel::kRigid) {
    const double y_r = d - p.clearance_m;
    return {y_r, d, kr * y_r + m * g};
  }
  const double ks = p.stator_stiffness_N_per_m, ms = p.stator_mass_kg;
  const double y_s = (ks * d - ms * g - m * g + kr * p.clearance_m) / (ks + kr);
  const double y_r = y_s - p.clearance_m;
  return {y_r, y_s, kr * y_r + m * g};
}

core::Sample rest_of(core::StatorModel stator, double d, core::Method method) {
  core::Scene s = test::paper_scene();
  s.model.stator_model = stator;
  s.model.eccentricity_m = 0.0;  // no unbalance, no spin: a static problem
  s.speed.target_speed_rad_per_s = 0.0;
  s.model.gravity_m_per_s2 = 9.81;
  s.model.stator_offset_y_m = d;
  s.end_time_s = 20.0;
  s.output_rate_hz = 10.0;
  s.solver.method = method;
  s.solver.rtol = method == core::Method::kPenalty ? 1e-8 : 1e-9;
  s.solver.atol = s.solver.rtol * 1e-3;
  const test::Run r = test::run(s);
  EXPECT_FALSE(r.result.failure.has_value()) << r.result.failure->message;
  return r.out.samples.back();
}

}  // namespace

TEST(StatorOffset, RestingOnTheBoreMatchesTheStaticClosedForm) {
  for (const auto stator : {core::StatorModel::kElastic, core::StatorModel::kRigid}) {
    // Elastic: 0.7 mm up gives N = 0.29 N; rigid: 0.5 mm up gives N = 0.36 N.
    const double d = stator == core::StatorModel::kElastic ? 7e-4 : 5e-4;
    core::ModelParameters p = test::paper_scene().model;
    p.stator_model = stator;
    p.gravity_m_per_s2 = 9.81;
    const Rest want = closed_form(p, d);
    ASSERT_GT(want.n, 0.0);
    for (const auto method : {core::Method::kSwitching, core::Method::kIteration, core::Method::kPenalty}) {
      const core::Sample s = rest_of(stator, d, method);
      const bool penalty = method == core::Method::kPenalty;
      const double tol_m = kRestTol_m + (penalty ? want.n / p.contact_stiffness_N_per_m : 0.0);
      EXPECT_TRUE(s.in_contact) << core::to_string(method);
      EXPECT_NEAR(s.kin.rotor_pos.y(), want.y_r, tol_m) << core::to_string(method);
      EXPECT_NEAR(s.kin.stator_pos.y(), want.y_s, tol_m) << core::to_string(method);
      EXPECT_NEAR(s.kin.rotor_pos.x(), 0.0, kRestTol_m);
      EXPECT_NEAR(s.normal_force_N, want.n, (penalty ? kPenaltyForceRelTol : kForceRelTol) * want.n)
          << core::to_string(method);
    }
  }
}

TEST(StatorOffset, ClearOfTheBoreBothSag) {
  const double d = 3e-4;  // the rotor's 1.645 mm sag stays 0.28 mm short of the bore
  const core::ModelParameters p = test::paper_scene().model;
  for (const auto method : {core::Method::kSwitching, core::Method::kIteration, core::Method::kPenalty}) {
    const core::Sample s = rest_of(core::StatorModel::kElastic, d, method);
    EXPECT_FALSE(s.in_contact);
    EXPECT_NEAR(s.kin.rotor_pos.y(), -p.rotor_mass_kg * 9.81 / p.rotor_stiffness_N_per_m, kRestTol_m);
    EXPECT_NEAR(s.kin.stator_pos.y(), d - p.stator_mass_kg * 9.81 / p.stator_stiffness_N_per_m, kRestTol_m);
  }
}

TEST(StatorOffset, AnOffsetBeyondTheClearanceIsRejected) {
  core::Scene s = test::paper_scene();
  s.model.stator_offset_x_m = 1.5e-3;
  s.model.stator_offset_y_m = 1.5e-3;  // |offset| 2.1 mm > C
  try {
    core::validate_scene(s);
    FAIL() << "accepted";
  } catch (const core::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("stator_offset_x_m"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("clearance_m"), std::string::npos) << e.what();
  }
}
