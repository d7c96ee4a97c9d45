#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "contact/angle_pair.hpp"
#include "methods/constrained_dynamics.hpp"
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

// k advanced by dt along a motion with constant accelerations ar, as.
Kinematics advanced(const Kinematics& k, const Vec2& ar, const Vec2& as, double dt) {
  Kinematics kk = k;
  kk.rotor_pos += k.rotor_vel * dt + 0.5 * ar * dt * dt;
  kk.stator_pos += k.stator_vel * dt + 0.5 * as * dt * dt;
  kk.rotor_vel += ar * dt;
  kk.stator_vel += as * dt;
  return kk;
}

}  // namespace

TEST(Model, NewtonsThirdLawForContactForces) {
  const JeffcottModel m{ModelParameters{}};
  const Kinematics k = pressed_state();
  const DriveState d{0.3, 150.0, 70.0};
  const ContactGeometry g = m.contact_geometry(k, d);
  const double fn = 12.5, ft = -0.7;
  const Accelerations a = m.accelerations(k, d, g, fn, ft);
  const Accelerations a0 = m.accelerations(k, d, g, 0.0, 0.0);
  const Vec2 on_rotor = (a.rotor - a0.rotor) / m.inv_rotor_mass();
  const Vec2 on_stator = (a.stator - a0.stator) / m.inv_stator_mass();
  EXPECT_NEAR((on_rotor + on_stator).norm(), 0.0, kForceTolerance_N);
  // Normal part pushes the rotor inward with F_n, the tangential part is F_t.
  EXPECT_NEAR(on_rotor.dot(g.normal), -fn, kForceTolerance_N);
  EXPECT_NEAR(on_rotor.dot(g.tangent), ft, kForceTolerance_N);
}

TEST(Model, SlidingAccelerationIsTheDerivativeOfSlidingVelocity) {
  // v_slide' from the model against a central difference of v_slide along
  // the motion (positions and velocities advanced with the accelerations).
  const JeffcottModel m{ModelParameters{}};
  const Kinematics k = pressed_state();
  const DriveState d{0.3, 150.0, 70.0};
  const ContactGeometry g = m.contact_geometry(k, d);
  const Accelerations a = m.accelerations(k, d, g, 12.5, -0.7);
  const Vec2 &ar = a.rotor, &as = a.stator;
  const double h = 1e-7;
  auto v_at = [&](double dt) {
    const Kinematics kk = advanced(k, ar, as, dt);
    const DriveState dd{d.angle_rad, d.speed_rad_per_s + d.accel_rad_per_s2 * dt, d.accel_rad_per_s2};
    return m.contact_geometry(kk, dd).sliding_velocity_m_per_s;
  };
  // Central difference: truncation O(h^2) and round-off 1e-16 / h ~ 1e-9 of
  // accelerations O(100) m/s^2: 1e-4 m/s^2 is ample, a wrong term is O(1).
  EXPECT_NEAR(m.sliding_acceleration(k, g, a), (v_at(h) - v_at(-h)) / (2 * h), 1e-4);
}

TEST(Model, FreeForceDerivativesAreTheRatesAlongTheMotion) {
  // The free flight's jerk in closed form (dense_high_order.hpp) stands on
  // rotor_/stator_free_force_derivative: against a central difference of
  // the free forces along a motion with these accelerations, the spin
  // advancing as the prescribed drive does (phi' = w, w' = A), with gravity
  // (constant: no rate) and both bodies moving.
  ModelParameters p;
  p.gravity_m_per_s2 = 9.81;
  const JeffcottModel m{p};
  const Kinematics k = pressed_state();
  const DriveState d{0.3, 150.0, 70.0};
  const Vec2 ar(-35.0, 12.0), as(4.0, -2.5);
  auto forces_at = [&](double dt) {
    const Kinematics kk = advanced(k, ar, as, dt);
    const DriveState dd{d.angle_rad + d.speed_rad_per_s * dt + 0.5 * d.accel_rad_per_s2 * dt * dt,
                        d.speed_rad_per_s + d.accel_rad_per_s2 * dt, d.accel_rad_per_s2};
    return std::make_pair(m.rotor_free_force(kk, dd), m.stator_free_force(kk));
  };
  const double h = 1e-6;
  const auto [fr_plus, fs_plus] = forces_at(h);
  const auto [fr_minus, fs_minus] = forces_at(-h);
  // Rates O(1e2..1e3) N/s (the unbalance's w^3 m e term is 5.6e2, the
  // springs' k v 3e2 and 8.5e2): the difference's truncation (w h)^2 / 6 ~ 4e-9
  // relative and round-off 1e-16 * 1e2 N / 1e-6 s ~ 1e-8 N/s; 1e-5 N/s is
  // ample, a missing or wrong term is O(1e2).
  EXPECT_LT((m.rotor_free_force_derivative(k, ar, d) - (fr_plus - fr_minus) / (2 * h)).norm(), 1e-5);
  EXPECT_LT((m.stator_free_force_derivative(k, as) - (fs_plus - fs_minus) / (2 * h)).norm(), 1e-5);
}

TEST(Model, FreeLoadsGiveTheSameAccelerationsToTheLastBit) {
  // The iteration method's roots and the samples take the free loads once
  // per state (model.hpp); the trajectories must not move by a bit for it.
  // Against the formulas as they were written before (each call taking its
  // own sin/cos and free forces), under both drives, with gravity and an
  // offset stator (test_golden.cpp holds whole runs).
  for (const DriveModel drive : {DriveModel::kPrescribed, DriveModel::kMotor}) {
    ModelParameters p;
    p.drive_model = drive;
    p.gravity_m_per_s2 = 9.81;
    p.stator_offset_x_m = 2e-4;
    const JeffcottModel m{p};
    Kinematics k = pressed_state();
    k.spin.angle_rad = 0.3;
    k.spin.speed_rad_per_s = 150.0;
    const DriveState d = m.drive_at(k, DriveState{0.3, 150.0, 70.0});
    const ContactGeometry g = m.contact_geometry(k, d);
    const FreeLoads free = m.free_loads(k, d);
    const double c = std::cos(d.angle_rad), s = std::sin(d.angle_rad);
    for (const double fn : {0.0, 12.5}) {
      const double ft = -0.1 * fn;
      const Vec2 on_rotor = JeffcottModel::contact_force_on_rotor(g, fn, ft);
      Accelerations before;
      if (drive == DriveModel::kPrescribed) {
        before.rotor = (m.rotor_free_force(k, d) + on_rotor) * m.inv_rotor_mass();
        before.spin_rad_per_s2 = d.accel_rad_per_s2;
      } else {
        const Vec2 at_centre = m.shaft_force(k) + on_rotor;
        before.spin_rad_per_s2 =
            (d.motor_torque_N_m + p.rotor_radius_m * ft + p.eccentricity_m * (at_centre.x() * s - at_centre.y() * c)) *
            (1.0 / p.rotor_polar_inertia_kg_m2);
        const double w2 = d.speed_rad_per_s * d.speed_rad_per_s;
        before.rotor = at_centre * m.inv_rotor_mass() + p.eccentricity_m * Vec2(w2 * c + before.spin_rad_per_s2 * s,
                                                                                w2 * s - before.spin_rad_per_s2 * c);
        before.rotor.y() -= p.gravity_m_per_s2;
      }
      before.stator = (m.stator_free_force(k) - on_rotor) * m.inv_stator_mass();
      const Accelerations a = m.accelerations(k, d, g, fn, ft);
      const Accelerations b = m.accelerations(d, g, free, fn, ft);
      // The two paths give the same bits; against the formulas as written
      // before, the same bits under the prescribed drive, and a motor's to
      // rounding: its spin coupling (SpinCoupling, which a flexible rotor's
      // station shares) groups e with the lever, not with the sum.
      EXPECT_EQ(a.rotor, b.rotor);
      EXPECT_EQ(a.stator, b.stator);
      EXPECT_EQ(a.spin_rad_per_s2, b.spin_rad_per_s2);
      const double ulps = drive == DriveModel::kPrescribed ? 0.0 : 4.0 * std::numeric_limits<double>::epsilon();
      EXPECT_LE((a.rotor - before.rotor).norm(), ulps * before.rotor.norm()) << to_string(drive);
      EXPECT_EQ(a.stator, before.stator) << to_string(drive);
      EXPECT_LE(std::abs(a.spin_rad_per_s2 - before.spin_rad_per_s2), ulps * std::abs(before.spin_rad_per_s2))
          << to_string(drive);
      if (drive == DriveModel::kPrescribed) {
        const Vec2 u(s, -c);
        const double torque_before = p.rotor_polar_inertia_kg_m2 * d.accel_rad_per_s2 - p.rotor_radius_m * ft -
                                     p.eccentricity_m * (m.shaft_force(k) + on_rotor).dot(u);
        // As a sample builds it: the station's J A - R_r F_t, then the
        // Jeffcott's lever e F . u from the sample's kinematics, which are
        // the casing's (the offset stator's frame shifted back).
        Kinematics casing = k;
        casing.rotor_pos += m.frame_shift();
        const double torque =
            m.station_drive_torque_N_m(d, ft) - m.unbalance_torque_N_m(casing, m.unbalance_dir(d.angle_rad), on_rotor);
        EXPECT_NEAR(torque, torque_before, 4.0 * std::numeric_limits<double>::epsilon() * std::abs(torque_before));
      }
    }
  }
}

namespace {

// The contact regime's closed-form jerk against a central difference of its
// derivative along the motion (x +- h x', the drive advanced as phi' = w,
// w' = A), for one stator model and friction regime.
template <int kStatorDof>
void expect_contact_jerk_closed_form(const ModelParameters& p, const FrictionMode& mode, const char* what) {
  using CD = ConstrainedDynamics<kStatorDof, false>;
  using L = typename CD::L;
  const JeffcottModel m{p};
  const JeffcottRotor rotor{p};
  CD dyn;
  dyn.model = &m;
  dyn.rotor = &rotor;
  dyn.mode = mode;
  typename L::State x;
  x[L::kAngle] = 7.3;  // a few turns on: psi keeps growing
  x[L::kAngleRate] = 140.0;
  if constexpr (kStatorDof == 2) {
    x.template segment<2>(L::kStatorPos) = Vec2(1e-4, -0.5e-4);
    x.template segment<2>(L::kStatorVel) = Vec2(0.01, 0.02);
  }
  const DriveState d{0.3, 150.0, 70.0};
  auto drive_at = [&](double dt) {
    return DriveState{d.angle_rad + d.speed_rad_per_s * dt + 0.5 * d.accel_rad_per_s2 * dt * dt,
                      d.speed_rad_per_s + d.accel_rad_per_s2 * dt, d.accel_rad_per_s2};
  };
  typename L::State dxdt, before, after, ddx;
  dyn.derivative(x, d, dxdt);
  const double h = 1e-6;
  dyn.derivative(typename L::State(x - h * dxdt), drive_at(-h), before);
  dyn.derivative(typename L::State(x + h * dxdt), drive_at(h), after);
  const typename L::State differenced = (after - before) / (2.0 * h);
  dyn.second_derivative(x, d, ddx);
  // Components from O(10) (the stator's acceleration) to O(1e6) (psi'''):
  // the difference's truncation (w h)^2 / 6 ~ 4e-9 relative and round-off
  // 1e-16 |x'| / h ~ 1e-10 |x'| (measured agreement ~1e-9 relative). Each
  // component within 1e-6 of itself, with a floor of 1e-9 of the largest
  // for one that vanishes (psi''' in stick); a missing or wrong term moves
  // a component by 1e-4 of itself or more.
  const double floor = 1e-9 * differenced.cwiseAbs().maxCoeff();
  for (int i = 0; i < L::kSize; ++i) {
    EXPECT_NEAR(ddx[i], differenced[i], 1e-6 * std::abs(differenced[i]) + floor) << what << ", component " << i;
  }
}

}  // namespace

TEST(ConstrainedDynamics, JerkIsTheDerivativeOfTheDerivativeAlongTheMotion) {
  // Slip both ways, stick, no friction; elastic stator (gravity, an offset)
  // and rigid stator.
  ModelParameters p;
  p.gravity_m_per_s2 = 9.81;
  p.stator_offset_x_m = 2e-4;
  p.friction_coefficient = 0.3;
  const FrictionMode forward{false, 1.0}, backward{false, -1.0}, stick{true, 1.0};
  expect_contact_jerk_closed_form<2>(p, forward, "elastic, slip s = +1");
  expect_contact_jerk_closed_form<2>(p, backward, "elastic, slip s = -1");
  expect_contact_jerk_closed_form<2>(p, stick, "elastic, stick");
  ModelParameters frictionless = p;
  frictionless.friction_coefficient = 0.0;
  expect_contact_jerk_closed_form<2>(frictionless, forward, "elastic, no friction");
  ModelParameters rigid = p;
  rigid.stator_model = StatorModel::kRigid;
  expect_contact_jerk_closed_form<0>(rigid, forward, "rigid, slip s = +1");
  expect_contact_jerk_closed_form<0>(rigid, stick, "rigid, stick");
}

TEST(ContactLaw, PenaltyFrictionNeverInjectsEnergyAndStaysInTheCone) {
  const JeffcottModel m{ModelParameters{}};
  const double c_t = tangential_damping_N_s_per_m(m);
  for (double v : {-5.0, -1e-3, -1e-7, 0.0, 1e-7, 1e-3, 5.0}) {
    const double ft = penalty_friction_N(0.3, 10.0, c_t, v);
    EXPECT_LE(ft * v, 0.0) << "v " << v;
    EXPECT_LE(std::abs(ft), 0.3 * 10.0) << "v " << v;
  }
  // Outside the creep band |v| > f F_n / c_t it is Coulomb's law exactly.
  EXPECT_EQ(penalty_friction_N(0.3, 10.0, c_t, 1e-3), -3.0);
  EXPECT_EQ(penalty_friction_N(0.3, 10.0, c_t, -1e-3), 3.0);
}

TEST(ContactLaw, FrictionModeAtRest) {
  // Sliding: the sign of v_slide.
  EXPECT_FALSE(select_friction_mode(0.2, false, 0.0, 1.0).stick);
  EXPECT_EQ(select_friction_mode(-0.2, false, 0.0, 1.0).slip_sign, -1.0);
  // At rest inside the cone: stick; outside: slide against the stick force.
  EXPECT_TRUE(select_friction_mode(0.0, true, 0.9, 1.0).stick);
  const FrictionMode up = select_friction_mode(0.0, true, 1.5, 1.0);
  EXPECT_FALSE(up.stick);
  EXPECT_EQ(up.slip_sign, -1.0);
  EXPECT_EQ(select_friction_mode(0.0, true, -1.5, 1.0).slip_sign, 1.0);
  // Without friction there is no stick, even with a zero stick force (the
  // stability campaign found a frictionless run held in stick, then
  // outside its zero cone).
  EXPECT_FALSE(select_friction_mode(0.0, true, 0.0, 0.0).stick);
}

TEST(ContactLaw, PlasticImpactStopsNormalMotionAndKeepsMomentum) {
  const JeffcottModel m{ModelParameters{}};
  Kinematics k = pressed_state();
  const DriveState d{0.0, 100.0, 0.0};
  const ContactGeometry g = m.contact_geometry(k, d);
  ASSERT_GT(g.normal_velocity_m_per_s, 0.0);
  const Vec2 p0 = k.rotor_vel / m.inv_rotor_mass() + k.stator_vel / m.inv_stator_mass();
  const ImpactResult r = apply_impact(m, g, d, 1e-9, k);
  const ContactGeometry after = m.contact_geometry(k, d);
  EXPECT_TRUE(r.settles);
  EXPECT_NEAR(after.normal_velocity_m_per_s, 0.0, 1e-15);
  // The friction impulse opposes the sliding and never reverses it.
  EXPECT_LE(std::abs(after.sliding_velocity_m_per_s), std::abs(g.sliding_velocity_m_per_s));
  EXPECT_GE(after.sliding_velocity_m_per_s * g.sliding_velocity_m_per_s, 0.0);
  const Vec2 p1 = k.rotor_vel / m.inv_rotor_mass() + k.stator_vel / m.inv_stator_mass();
  EXPECT_NEAR((p1 - p0).norm(), 0.0, 1e-15);
}

TEST(ContactLaw, RestitutionReversesNormalVelocity) {
  ModelParameters p;
  p.restitution = 0.5;
  const JeffcottModel m{p};
  Kinematics k = pressed_state();
  const DriveState d{0.0, 100.0, 0.0};
  const ContactGeometry g = m.contact_geometry(k, d);
  const ImpactResult r = apply_impact(m, g, d, 1e-9, k);
  EXPECT_FALSE(r.settles);
  EXPECT_NEAR(m.contact_geometry(k, d).normal_velocity_m_per_s, -0.5 * g.normal_velocity_m_per_s, 1e-15);
}

TEST(ContactLaw, ReboundBelowTheToleranceSettles) {
  // Apex (e v)^2 / (2 a_press) below settle_apex_m: plastic.
  ModelParameters p;
  p.restitution = 0.5;
  p.gravity_m_per_s2 = 20.0;
  p.stator_model = StatorModel::kRigid;
  p.rotor_damping_N_s_per_m = 0.0;
  const JeffcottModel m{p};
  Kinematics k;
  k.rotor_pos = Vec2(0.0, -p.clearance_m);
  k.rotor_vel = Vec2(0.0, -1e-4);
  const DriveState d{0.0, 0.0, 0.0};
  const ContactGeometry g = m.contact_geometry(k, d);
  const double a_press = pressing_acceleration(m, k, d, g);
  EXPECT_NEAR(a_press, 20.0 - p.rotor_stiffness_N_per_m * p.clearance_m / p.rotor_mass_kg, 1e-12);
  const double apex = std::pow(0.5e-4, 2) / (2 * a_press);
  Kinematics k1 = k, k2 = k;
  EXPECT_FALSE(apply_impact(m, g, d, 0.5 * apex, k1).settles);
  EXPECT_TRUE(apply_impact(m, g, d, 2.0 * apex, k2).settles);
}

TEST(ContactLaw, ClampedDashpotRestitutionClosedForm) {
  // The closed form's limits: undamped elastic, critical exp(-2), and the
  // overdamped tail e ~ 1 / (4 zeta^2); continuity across zeta = 1.
  EXPECT_EQ(clamped_dashpot_restitution(0.0), 1.0);
  EXPECT_NEAR(clamped_dashpot_restitution(1.0), std::exp(-2.0), 1e-15);
  EXPECT_NEAR(clamped_dashpot_restitution(1.0 - 1e-9), std::exp(-2.0), 1e-6);
  EXPECT_NEAR(clamped_dashpot_restitution(1.0 + 1e-9), std::exp(-2.0), 1e-6);
  EXPECT_NEAR(clamped_dashpot_restitution(50.0) * 4 * 50.0 * 50.0, 1.0, 0.01);
  // The inversion hits every e in [floor, 1] (root tolerance 1e-14).
  for (double e : {kPenaltyRestitutionFloor, 0.05, 0.1, 0.3, 0.5, 0.8, 0.99}) {
    EXPECT_NEAR(clamped_dashpot_restitution(contact_damping_ratio(e)), e, 1e-12) << e;
  }
  EXPECT_EQ(contact_damping_ratio(1.0), 0.0);
  EXPECT_EQ(contact_damping_ratio(0.0), contact_damping_ratio(kPenaltyRestitutionFloor));
  // The floor: 0.01 up to k_c 1e9, then falling as k_c^-1/2 so that the
  // penalty method keeps converging as k_c grows.
  EXPECT_EQ(penalty_restitution_floor(1e8), 0.01);
  EXPECT_EQ(penalty_restitution_floor(1e9), 0.01);
  EXPECT_NEAR(penalty_restitution_floor(1e11), 0.001, 1e-15);
  ModelParameters stiff;
  stiff.restitution = 0.0;
  stiff.contact_stiffness_N_per_m = 1e11;
  EXPECT_NEAR(clamped_dashpot_restitution(contact_damping_ratio(stiff)), 0.001, 1e-12);
}

TEST(ContactLaw, ClampedDashpotRestitutionAgainstIntegration) {
  // The closed form against a direct integration of m x'' = -max(0, k x +
  // c x') from x = 0, x' = v0 until the force vanishes (semi-implicit Euler,
  // 1e6 steps per natural period: first-order error ~1e-5 relative).
  for (double zeta : {0.1, 0.5, 0.9, 1.5, 4.0}) {
    const double w0 = 1.0, v0 = 1.0, h = 2 * M_PI / w0 * 1e-6;
    double x = 0.0, v = v0;
    for (int i = 0; i < 100000000; ++i) {
      const double f = -(w0 * w0 * x + 2 * zeta * w0 * v);
      if (i > 0 && f >= 0.0) break;
      v += h * f;
      x += h * v;
    }
    EXPECT_NEAR(-v / v0, clamped_dashpot_restitution(zeta), 1e-4) << "zeta " << zeta;
  }
}
