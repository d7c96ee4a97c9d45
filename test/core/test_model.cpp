#include <gtest/gtest.h>

#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/model.hpp"

using namespace rotor_rub::core;

namespace {

// A rotor pressed into the bore, moving and spinning.
Kinematics pressed_state() {
  Kinematics k;
  k.rotor_pos = Vec2(1.5e-3, 1.5e-3);
  k.stator_pos = Vec2(1e-4, -0.5e-4);
  k.rotor_vel = Vec2(0.12, 0.05);  // closing on the bore
  k.stator_vel = Vec2(0.01, 0.02);
  return k;
}

// Round-off of sums of O(1e2) N forces.
constexpr double kForceTolerance_N = 1e-9;

}  // namespace

TEST(Model, NewtonsThirdLawForContactForces) {
  const JeffcottModel m{ModelParameters{}};
  const Kinematics k = pressed_state();
  const DriveState d{0.3, 150.0, 70.0};
  const ContactGeometry g = m.contact_geometry(k, d);
  const double fn = 12.5;
  Vec2 ar, as, ar0, as0;
  m.accelerations(k, d, g, fn, ar, as);
  m.accelerations(k, d, g, 0.0, ar0, as0);
  const Vec2 on_rotor = (ar - ar0) / m.inv_rotor_mass();
  const Vec2 on_stator = (as - as0) / m.inv_stator_mass();
  EXPECT_NEAR((on_rotor + on_stator).norm(), 0.0, kForceTolerance_N);
  // Normal part pushes the rotor inward with F_n, friction is f F_n.
  EXPECT_NEAR(on_rotor.dot(g.normal), -fn, kForceTolerance_N);
  EXPECT_NEAR(std::abs(on_rotor.dot(g.tangent)), m.parameters().friction_coefficient * fn, kForceTolerance_N);
}

TEST(Model, FrictionNeverInjectsEnergy) {
  const JeffcottModel m{ModelParameters{}};
  for (double w : {-300.0, -50.0, -1e-3, 0.0, 1e-3, 50.0, 300.0}) {
    for (double vt : {-0.5, -1e-5, 0.0, 1e-5, 0.5}) {
      Kinematics k = pressed_state();
      const ContactGeometry g0 = m.contact_geometry(k, {0.0, w, 0.0});
      k.rotor_vel += (vt - (k.rotor_vel - k.stator_vel).dot(g0.tangent)) * g0.tangent;
      const ContactGeometry g = m.contact_geometry(k, {0.0, w, 0.0});
      const Vec2 f = 10.0 * m.contact_direction(g);
      // Power of the friction pair on the sliding velocity at the contact.
      const double power = f.dot(g.tangent) * g.sliding_velocity_m_per_s;
      EXPECT_LE(power, 0.0) << "w " << w << " vt " << vt;
    }
  }
}

TEST(Model, FrictionFlipsWithSpin) {
  const JeffcottModel m{ModelParameters{}};
  Kinematics k = pressed_state();
  k.rotor_vel = k.stator_vel;  // no whirl: sliding from spin only
  const ContactGeometry fwd = m.contact_geometry(k, {0.0, 100.0, 0.0});
  const ContactGeometry bwd = m.contact_geometry(k, {0.0, -100.0, 0.0});
  EXPECT_LT(m.contact_direction(fwd).dot(fwd.tangent), 0.0);
  EXPECT_GT(m.contact_direction(bwd).dot(bwd.tangent), 0.0);
}

TEST(Model, FrictionlessSceneSkipsFriction) {
  ModelParameters p;
  p.friction_coefficient = 0.0;
  const JeffcottModel m{p};
  const Kinematics k = pressed_state();
  const ContactGeometry g = m.contact_geometry(k, {0.0, 100.0, 0.0});
  EXPECT_FALSE(m.has_friction());
  EXPECT_NEAR(m.contact_direction(g).dot(g.tangent), 0.0, 1e-15);
}

TEST(ContactLaw, PlasticImpactStopsNormalMotionAndKeepsMomentum) {
  const JeffcottModel m{ModelParameters{}};
  Kinematics k = pressed_state();
  const ContactGeometry g = m.contact_geometry(k, {0.0, 100.0, 0.0});
  ASSERT_GT(g.normal_velocity_m_per_s, 0.0);
  const Vec2 p0 = k.rotor_vel / m.inv_rotor_mass() + k.stator_vel / m.inv_stator_mass();
  const ImpactResult r = apply_impact(m, g, k);
  const ContactGeometry after = m.contact_geometry(k, {0.0, 100.0, 0.0});
  EXPECT_TRUE(r.settles);
  EXPECT_NEAR(after.normal_velocity_m_per_s, 0.0, 1e-15);
  const Vec2 p1 = k.rotor_vel / m.inv_rotor_mass() + k.stator_vel / m.inv_stator_mass();
  EXPECT_NEAR((p1 - p0).norm(), 0.0, 1e-15);
}

TEST(ContactLaw, RestitutionReversesNormalVelocity) {
  ModelParameters p;
  p.restitution = 0.5;
  const JeffcottModel m{p};
  Kinematics k = pressed_state();
  const ContactGeometry g = m.contact_geometry(k, {0.0, 100.0, 0.0});
  apply_impact(m, g, k);
  EXPECT_NEAR(m.contact_geometry(k, {0.0, 100.0, 0.0}).normal_velocity_m_per_s, -0.5 * g.normal_velocity_m_per_s,
              1e-15);
}

TEST(ContactLaw, PenaltyDampingFollowsRestitution) {
  EXPECT_EQ(contact_damping_ratio(0.0), 1.0);
  EXPECT_EQ(contact_damping_ratio(1.0), 0.0);
  // Linear spring-dashpot: e = exp(-zeta pi / sqrt(1 - zeta^2)).
  const double z = contact_damping_ratio(0.5);
  EXPECT_NEAR(std::exp(-z * M_PI / std::sqrt(1 - z * z)), 0.5, 1e-12);
}
