// The motor drive (drive_model motor, model.hpp): the spin as a state under
// a PI speed controller with a torque limit, loaded by the rub's friction
// torque. Checked against closed forms (spin-up in the torque limit, the
// power balance of the coupled rotor-spin equations in free flight, the
// torque balance of the steady synchronous full rub), against each other
// (all three methods on config/machine_runup.yaml). The prescribed drive's
// runs are held to their figures by test_golden.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/steady_response.hpp"
#include "run_output.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

core::Scene motor_scene(core::Scene s) {
  s.model.drive_model = core::DriveModel::kMotor;
  return s;
}

// Kinetic plus potential energy of rotor, spin and stator [J] (no gravity):
// the mass centre moves at v_r + e w (-sin phi, cos phi).
double energy_J(const core::ModelParameters& p, const core::Sample& s) {
  const double phi = s.drive.angle_rad, w = s.drive.speed_rad_per_s;
  const core::Vec2 v_mass = s.kin.rotor_vel + p.eccentricity_m * w * core::Vec2(-std::sin(phi), std::cos(phi));
  const core::Vec2 stator_rest(p.stator_offset_x_m, p.stator_offset_y_m);
  double e = 0.5 * p.rotor_mass_kg * v_mass.squaredNorm() + 0.5 * p.rotor_polar_inertia_kg_m2 * w * w +
             0.5 * p.rotor_stiffness_N_per_m * s.kin.rotor_pos.squaredNorm();
  if (p.stator_model == core::StatorModel::kElastic) {
    e += 0.5 * p.stator_mass_kg * s.kin.stator_vel.squaredNorm() +
         0.5 * p.stator_stiffness_N_per_m * (s.kin.stator_pos - stator_rest).squaredNorm();
  }
  return e;
}

// Power in minus the losses [W]: the drive's, the dampers', the friction's.
double net_power_W(const core::ModelParameters& p, const core::Sample& s) {
  double w = s.drive_torque_N_m * s.drive.speed_rad_per_s - p.rotor_damping_N_s_per_m * s.kin.rotor_vel.squaredNorm() +
             s.friction_force_N * s.sliding_velocity_m_per_s;
  if (p.stator_model == core::StatorModel::kElastic) w -= p.stator_damping_N_s_per_m * s.kin.stator_vel.squaredNorm();
  return w;
}

}  // namespace

TEST(MotorDrive, SpinUpInTheTorqueLimitFollowsTheClosedForm) {
  // No unbalance, no gravity: the rotor stays centred and the spin sees only
  // the motor. A reference ramp far steeper than the limit allows keeps the
  // motor at T_max until the speed nears the target: w = T_max t / J_G
  // exactly (dopri5 integrates a linear function without error beyond
  // rounding).
  for (const auto method : {core::Method::kSwitching, core::Method::kIteration, core::Method::kPenalty}) {
    core::Scene s = motor_scene(test::paper_scene());
    s.solver.method = method;
    s.model.eccentricity_m = 0.0;
    s.speed.acceleration_rad_per_s2 = 1e4;
    s.speed.target_speed_rad_per_s = 200.0;
    s.end_time_s = 1.5;
    const double t_max = s.model.drive_torque_limit_N_m, j = s.model.rotor_polar_inertia_kg_m2;
    const test::Run r = test::run(s);
    ASSERT_FALSE(r.result.failure.has_value()) << r.result.failure->message;
    double peak = 0.0;
    for (const auto& x : r.out.samples) {
      const double closed = t_max * x.t_s / j;
      if (closed < 0.9 * s.speed.target_speed_rad_per_s) {
        EXPECT_NEAR(x.drive.speed_rad_per_s, closed, 1e-9 * closed + 1e-12)
            << core::to_string(method) << " t " << x.t_s;
        EXPECT_DOUBLE_EQ(x.drive_torque_N_m, t_max) << x.t_s;
        EXPECT_NEAR(x.drive.accel_rad_per_s2, t_max / j, 1e-9 * t_max / j);
      }
      EXPECT_EQ(x.kin.rotor_pos.norm(), 0.0);
      peak = std::max(peak, x.drive.speed_rad_per_s);
    }
    // Anti-windup: after 0.4 s in the limit the integrator holds T_max / K_i
    // (back-calculation), not the 0.4 s x 100 rad/s of error it would have
    // wound up; the overshoot stays at the PI loop's own (measured 1.2 %).
    EXPECT_LT(peak, 1.02 * s.speed.target_speed_rad_per_s) << core::to_string(method);
    EXPECT_NEAR(r.out.samples.back().drive.speed_rad_per_s, s.speed.target_speed_rad_per_s, 1e-6);
  }
}

TEST(MotorDrive, PowerBalanceOfTheCoupledSpinInFreeFlight) {
  // A run-up through the critical speed with a wide clearance (no contact):
  // the energy of rotor and spin (the mass centre's motion, J_G w^2 / 2, the
  // shaft spring) grows by the motor's work less the damper's loss. Without
  // the unbalance's reaction torque e F . u in the spin equation the balance
  // is off by the damper's loss through the resonance (0.084 J measured, 200x
  // the tolerance below).
  core::Scene s = motor_scene(test::paper_scene());
  s.model.clearance_m = 0.05;
  s.output_rate_hz = 20000.0;
  s.solver.rtol = 1e-10;
  s.solver.atol = 1e-13;
  const test::Run r = test::run(s);
  ASSERT_FALSE(r.result.failure.has_value()) << r.result.failure->message;
  const auto& x = r.out.samples;
  double work = 0.0, loss_at_resonance = 0.0;
  for (std::size_t k = 1; k < x.size(); ++k) {
    const double dt = x[k].t_s - x[k - 1].t_s;
    work += 0.5 * dt * (net_power_W(s.model, x[k]) + net_power_W(s.model, x[k - 1]));
    loss_at_resonance += dt * s.model.rotor_damping_N_s_per_m * x[k].kin.rotor_vel.squaredNorm();
  }
  const double gained = energy_J(s.model, x.back()) - energy_J(s.model, x.front());
  ASSERT_GT(loss_at_resonance, 0.05);  // the check is not vacuous
  // Trapezoid error with 20 kHz samples of a power oscillating at <= 45 Hz:
  // (h w)^2 / 12 ~ 2e-5 of the oscillating part; 1e-5 of the 39 J gained
  // bounds it with room.
  EXPECT_NEAR(gained, work, 1e-5 * gained) << "gained " << gained << " J, work " << work << " J";
}

TEST(MotorDrive, SteadyFullRubTorqueBalance) {
  // Held at w in synchronous full annular rub (steady_response.hpp): the PI
  // loop holds w exactly, so the orbit and N are the prescribed drive's
  // closed form; the motor then supplies the friction's and the dampers'
  // power, T_m w = f N v_slide + b_r |v_r|^2 + b_s |v_s|^2, and its torque is
  // f N R_r plus the unbalance's reaction.
  struct Case {
    const char* name;
    core::StatorModel stator;
    double friction, speed_rad_per_s;
  };
  const Case cases[] = {{"elastic stator, f 0.3, 120 rad/s", core::StatorModel::kElastic, 0.3, 120.0},
                        {"rigid stator, f 0.1, 400 rad/s", core::StatorModel::kRigid, 0.1, 400.0}};
  for (const auto& c : cases) {
    core::Scene s = motor_scene(test::paper_scene());
    s.model.stator_model = c.stator;
    s.model.friction_coefficient = c.friction;
    s.model.drive_torque_limit_N_m = 10.0;  // the rub's torque must not saturate it here
    s.speed.target_speed_rad_per_s = c.speed_rad_per_s;
    s.speed.max_speed_rad_per_s = std::max(s.speed.max_speed_rad_per_s, c.speed_rad_per_s);
    s.end_time_s = c.speed_rad_per_s / s.speed.acceleration_rad_per_s2 + 8.0;
    s.output_rate_hz = 500.0;
    s.solver.rtol = 1e-9;
    s.solver.atol = 1e-12;
    const auto branch = core::synchronous_full_rub(s.model, c.speed_rad_per_s);
    ASSERT_FALSE(branch.empty()) << c.name;
    for (const auto method : {core::Method::kSwitching, core::Method::kIteration}) {
      s.solver.method = method;
      const test::Run r = test::run(s);
      ASSERT_FALSE(r.result.failure.has_value()) << c.name << ": " << r.result.failure->message;
      const core::Sample& x = r.out.samples.back();
      ASSERT_TRUE(x.in_contact) << c.name;
      EXPECT_NEAR(x.drive.speed_rad_per_s, c.speed_rad_per_s, 1e-7 * c.speed_rad_per_s) << c.name;
      EXPECT_NEAR(x.normal_force_N, branch.front().normal_force_N, 1e-6 * branch.front().normal_force_N) << c.name;
      const double losses =
          -x.friction_force_N * x.sliding_velocity_m_per_s +
          s.model.rotor_damping_N_s_per_m * x.kin.rotor_vel.squaredNorm() +
          (c.stator == core::StatorModel::kElastic ? s.model.stator_damping_N_s_per_m * x.kin.stator_vel.squaredNorm()
                                                   : 0.0);
      EXPECT_NEAR(x.drive_torque_N_m * x.drive.speed_rad_per_s, losses, 1e-6 * losses)
          << c.name << " " << core::to_string(method);
      EXPECT_NEAR(x.friction_torque_N_m, -c.friction * x.normal_force_N * s.model.rotor_radius_m,
                  1e-9 * x.normal_force_N)
          << c.name;
      EXPECT_GT(x.drive_torque_N_m, -x.friction_torque_N_m) << c.name;  // and the dampers' share on top
    }
  }
}

TEST(MotorDrive, MethodsAgreeOnTheMachineScene) {
  // config/machine_runup.yaml: the rub drives the motor into its torque
  // limit (the speed falls behind the reference). The rigid methods model
  // the same contact exactly: they agree to their tolerance; penalty to its
  // compliance (the paper scene's floor, docs/benchmarks.md).
  const core::Scene base = core::load_scene(test::source_path("config/machine_runup.yaml"));
  ASSERT_EQ(base.model.drive_model, core::DriveModel::kMotor);
  std::vector<test::Run> runs;
  const std::vector<test::Solver> solvers = test::all_solvers();  // switching (dopri5) first, penalty last
  for (const auto& solver : solvers) {
    const core::Method method = solver.method;
    core::Scene s = base;
    s.solver.method = method;
    s.solver.integrator = solver.integrator;
    s.solver.rtol = method == core::Method::kPenalty ? 1e-7 : 1e-9;
    s.solver.atol = s.solver.rtol * 1e-3;
    runs.push_back(test::run(s));
    ASSERT_FALSE(runs.back().result.failure.has_value()) << runs.back().result.failure->message;
  }
  const auto& sw = runs[0].out.samples;
  double lag = 0.0, saturated_s = 0.0;
  for (std::size_t m = 1; m < runs.size(); ++m) {
    const auto& other = runs[m].out.samples;
    ASSERT_EQ(other.size(), sw.size());
    double orbit = 0.0, speed = 0.0;
    for (std::size_t k = 0; k < sw.size(); ++k) {
      orbit = std::max(orbit, (other[k].kin.rotor_pos - sw[k].kin.rotor_pos).norm());
      speed = std::max(speed, std::abs(other[k].drive.speed_rad_per_s - sw[k].drive.speed_rad_per_s));
    }
    // Measured: iteration 2e-9 m, 5e-7 rad/s; switching on rkf78 (the spin
    // angle and speed interpolated as a pair, the controller's integral
    // alone) 9e-10 m, 5e-7 rad/s (rotor_rub_run at rtol 1e-10); penalty 3e-6 m, 5e-3 rad/s.
    const bool penalty = solvers[m].method == core::Method::kPenalty;
    EXPECT_LT(orbit, penalty ? 4e-5 : 1e-7) << solvers[m].name();
    EXPECT_LT(speed, penalty ? 0.05 : 1e-4) << solvers[m].name();
  }
  for (const auto& x : sw) {
    const double reference = std::min(70.0 * x.t_s, 280.0);
    lag = std::max(lag, reference - x.drive.speed_rad_per_s);
    if (x.drive_torque_N_m == base.model.drive_torque_limit_N_m && x.in_contact) saturated_s += 1e-3;
  }
  EXPECT_GT(lag, 5.0);          // the rub is seen as a speed dip (measured 8.4 rad/s)
  EXPECT_GT(saturated_s, 0.3);  // with the motor in its limit while it rubs
  EXPECT_NEAR(sw.back().drive.speed_rad_per_s, 280.0, 1e-3);
}

TEST(MotorDrive, RigidMethodsAgreeBeyondThePaperScene) {
  // Scenes the paper does not have, under the motor: a rigid stator with
  // gravity, restitution 0.5 and f 0.3 (bounces, stick and slip with the spin
  // coupled), and f 0.8 far above the critical speed. Both rigid methods model
  // the same contact exactly: they agree to their tolerance (rtol 1e-9),
  // and neither breaks an invariant (a failure would be reported).
  struct Case {
    const char* name;
    const char* sets[5];
  };
  const Case cases[] = {
      {"rigid, gravity, e 0.5, f 0.3",
       {"stator_model=rigid", "gravity_m_per_s2=9.81", "restitution=0.5", "friction_coefficient=0.3", "end_time_s=3"}},
      {"elastic, f 0.8, to 400 rad/s",
       {"friction_coefficient=0.8", "target_speed_rad_per_s=400", "acceleration_rad_per_s2=200", "end_time_s=2.5",
        "drive_torque_limit_N_m=1"}},
  };
  for (const auto& c : cases) {
    core::Scene s = core::load_scene(test::source_path("config/machine_runup.yaml"));
    for (const char* item : c.sets) {
      const std::string kv(item);
      core::set_scene_value(s, kv.substr(0, kv.find('=')), kv.substr(kv.find('=') + 1));
    }
    s.solver.rtol = 1e-9;
    s.solver.atol = 1e-12;
    std::vector<test::Run> runs;
    for (const auto method : {core::Method::kSwitching, core::Method::kIteration}) {
      s.solver.method = method;
      runs.push_back(test::run(s));
      ASSERT_FALSE(runs.back().result.failure.has_value()) << c.name << ": " << runs.back().result.failure->message;
    }
    const auto &a = runs[0].out.samples, &b = runs[1].out.samples;
    ASSERT_EQ(a.size(), b.size());
    double orbit = 0.0, speed = 0.0, contact_s = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) {
      orbit = std::max(orbit, (a[k].kin.rotor_pos - b[k].kin.rotor_pos).norm());
      speed = std::max(speed, std::abs(a[k].drive.speed_rad_per_s - b[k].drive.speed_rad_per_s));
      if (a[k].in_contact) contact_s += 1.0 / s.output_rate_hz;
    }
    EXPECT_GT(contact_s, 0.05) << c.name;  // the scene does rub
    std::printf("[ measured ] %s: |dr| %.2g m, |dw| %.2g rad/s, contact %.3f s\n", c.name, orbit, speed, contact_s);
    // Measured: 3.6e-7 m and 2.1e-4 rad/s with the bounces (each rebound's
    // time carries the tolerance into the next flight), 3e-12 m without;
    // the bounds leave a factor 3-5.
    EXPECT_LT(orbit, 1e-6) << c.name;
    EXPECT_LT(speed, 1e-3) << c.name;
  }
}

TEST(MotorDrive, SpeedCommandsMoveTheReferenceTheMotorFollows) {
  // A command mid-run (as the node's speed_command) restarts every method
  // from its own state, spin included, and the PI loop takes the new
  // reference: down from the run-up to 50 rad/s, and back up to 120.
  for (const auto method : {core::Method::kSwitching, core::Method::kIteration, core::Method::kPenalty}) {
    core::Scene s = core::load_scene(test::source_path("config/machine_runup.yaml"));
    s.solver.method = method;
    s.end_time_s = 6.0;
    core::Simulation sim(s);
    test::Collect out;
    ASSERT_TRUE(sim.advance_to(1.5, out));  // 105 rad/s, rubbing
    const double before = out.samples.back().drive.speed_rad_per_s;
    sim.command_speed(50.0, 100.0);
    ASSERT_TRUE(sim.advance_to(1.5 + 1e-3, out));
    EXPECT_NEAR(out.samples.back().drive.speed_rad_per_s, before, 0.5);  // continuous: no jump at the command
    ASSERT_TRUE(sim.advance_to(3.0, out));
    EXPECT_NEAR(out.samples.back().drive.speed_rad_per_s, 50.0, 1e-3) << core::to_string(method);
    sim.command_speed(120.0, 100.0);
    ASSERT_TRUE(sim.advance_to(6.0, out)) << sim.failure()->message;
    EXPECT_NEAR(out.samples.back().drive.speed_rad_per_s, 120.0, 1e-3) << core::to_string(method);
  }
}

TEST(MotorDrive, KeyphasorMarksTheIntegratedSpinAngle) {
  core::Scene s = core::load_scene(test::source_path("config/machine_runup.yaml"));
  s.end_time_s = 3.0;
  tools::RunRecorder rec(true, true);
  const core::RunResult r = core::run_scene(s, rec);
  ASSERT_FALSE(r.failure.has_value());
  const double final_angle = rec.samples.back().drive.angle_rad;
  EXPECT_EQ(static_cast<long>(rec.marks.size()), static_cast<long>(std::floor(final_angle / (2 * M_PI))));
  for (std::size_t k = 0; k < rec.marks.size(); ++k) {
    // Located to 1e-13 s: the angle is 2 pi (k + 1) to w x 1e-13 rad.
    EXPECT_NEAR(rec.marks[k].drive.angle_rad, 2 * M_PI * static_cast<double>(k + 1), 1e-9) << k;
  }
}

TEST(MotorDrive, ImpactWithSpinWithoutUnbalanceHasItsClosedForm) {
  // e = 0 decouples the normal impulse from the spin: P_n = (1 + e_r) v_n
  // m_eff; the tangential impulse -f P_n s changes the spin by R_r P_t / J_G
  // and the sliding by P_t (1/m_eff + R_r^2 / J_G), or stops the sliding
  // exactly when that would reverse it.
  core::ModelParameters p;
  p.drive_model = core::DriveModel::kMotor;
  p.eccentricity_m = 0.0;
  p.restitution = 0.5;
  p.friction_coefficient = 0.3;
  const core::JeffcottModel m(p);
  const double m_eff = m.effective_mass_kg(), j = p.rotor_polar_inertia_kg_m2, r = p.rotor_radius_m;
  for (const double spin : {100.0, 0.5}) {  // sliding throughout; sliding stopped
    core::Kinematics k;
    k.rotor_pos = core::Vec2(2.0e-3, 0.0);
    k.rotor_vel = core::Vec2(0.05, 0.0);  // closing at 5 cm/s
    k.spin.speed_rad_per_s = spin;
    core::DriveState d;
    d.speed_rad_per_s = spin;
    const core::ContactGeometry g = m.contact_geometry(k, d);
    core::Kinematics after = k;
    const core::ImpactResult ir = core::apply_impact(m, g, d, 0.0, after);
    EXPECT_NEAR(ir.normal_impulse_N_s, 1.5 * 0.05 * m_eff, 1e-15);
    const double slide_before = g.sliding_velocity_m_per_s;
    const double slide_after =
        m.contact_geometry(after, core::DriveState{0, after.spin.speed_rad_per_s, 0, 0}).sliding_velocity_m_per_s;
    const double pt_sliding = -0.3 * ir.normal_impulse_N_s;
    if (slide_before + pt_sliding * (1.0 / m_eff + r * r / j) > 0.0) {
      EXPECT_FALSE(ir.sliding_stopped);
      EXPECT_NEAR(after.spin.speed_rad_per_s - spin, r * pt_sliding / j, 1e-12);
      EXPECT_NEAR(slide_after, slide_before + pt_sliding * (1.0 / m_eff + r * r / j), 1e-12);
    } else {
      EXPECT_TRUE(ir.sliding_stopped);
      EXPECT_NEAR(slide_after, 0.0, 1e-15);
    }
    EXPECT_NEAR(m.contact_geometry(after, d).normal_velocity_m_per_s, -0.5 * 0.05, 1e-15);
  }
}

// The impact with the spin against the impact followed in small steps of
// its normal impulse (Darboux-Keller), written from the model's impulse
// response alone (apply_impulse, contact_geometry), not from W: each step
// dP_n takes the tangential increment of Coulomb's law at the step's end
// (sliding on with the cone's edge against the sliding, or the increment
// that holds v_slide = 0 if one lies in the cone), and the impact ends where
// v_n reaches -e v_n. Large unbalance lever (W_nt large) and low friction:
// some impacts stop the sliding and then slide back (|W_nt| > f W_tt),
// others stick, others slide throughout. Held to 1e-4 of the velocities'
// scale: the steps resolve the phase changes to 1/kSteps of the impulse.
TEST(MotorDrive, ImpactWithSpinFollowsTheIncrementalImpact) {
  constexpr int kSteps = 100000;
  core::ModelParameters p;
  p.drive_model = core::DriveModel::kMotor;
  p.eccentricity_m = 2e-3;
  p.rotor_polar_inertia_kg_m2 = 2e-5;
  int slid_back = 0, stuck = 0, slid_through = 0;
  for (const double f : {0.05, 0.3}) {
    for (const double restitution : {0.0, 0.5}) {
      for (const double phi : {0.0, 0.7, 1.6, 2.5, 3.9, 5.2}) {
        for (const double vt : {-0.02, 0.0, 0.005}) {  // tangential relative velocity [m/s]
          p.friction_coefficient = f;
          p.restitution = restitution;
          const core::JeffcottModel m(p);
          core::Kinematics k;
          k.rotor_pos = core::Vec2(2.0e-3, 0.0);
          k.rotor_vel = core::Vec2(0.05, vt);  // closing at 5 cm/s
          k.spin.angle_rad = phi;
          k.spin.speed_rad_per_s = 0.3;  // v_slide = vt + 3 mm/s
          const core::DriveState d = m.drive_at(k, core::DriveState{phi, 0.3, 0.0, 0.0});
          auto geometry = [&](const core::Kinematics& kin) {
            return m.contact_geometry(kin, core::DriveState{phi, kin.spin.speed_rad_per_s, 0.0, 0.0});
          };
          const core::ContactGeometry g = geometry(k);
          const double target = -restitution * g.normal_velocity_m_per_s;
          // The reference: steps of a normal impulse a little beyond the
          // frictionless one over kSteps.
          const double dp = 2.0 * g.normal_velocity_m_per_s * m.effective_mass_kg() / kSteps;
          core::Kinematics ref = k;
          bool was_stuck = false, reversed = false, ended_stuck = false;
          const double s0 = g.sliding_velocity_m_per_s > 0 ? 1 : (g.sliding_velocity_m_per_s < 0 ? -1 : 0);
          for (int i = 0; i < 4 * kSteps; ++i) {
            auto after = [&](double pn, double pt) {
              core::Kinematics t = ref;
              m.apply_impulse(g, pn, pt, t);
              return t;
            };
            const double lo = geometry(after(dp, -f * dp)).sliding_velocity_m_per_s;
            const double hi = geometry(after(dp, f * dp)).sliding_velocity_m_per_s;
            double pt;
            bool stick_step = false;
            if (lo > 0.0) {
              pt = -f * dp;
            } else if (hi < 0.0) {
              pt = f * dp;
            } else {  // v_slide is affine in P_t: the increment that zeroes it
              pt = -f * dp + 2.0 * f * dp * lo / (lo - hi);
              was_stuck = stick_step = true;
            }
            ended_stuck = stick_step;
            const core::Kinematics next = after(dp, pt);
            const double vn0 = geometry(ref).normal_velocity_m_per_s, vn1 = geometry(next).normal_velocity_m_per_s;
            if (vn1 <= target) {  // the last step's share that reaches the target (affine in the step)
              const double share = (vn0 - target) / (vn0 - vn1);
              ref = after(share * dp, share * pt);
              break;
            }
            ref = next;
            const double vs = geometry(ref).sliding_velocity_m_per_s;
            if (s0 != 0.0 && s0 * vs < -1e-9) reversed = true;
          }
          core::Kinematics got = k;
          const core::ImpactResult ir = core::apply_impact(m, g, d, 0.0, got);
          const std::string where = "f " + std::to_string(f) + " e " + std::to_string(restitution) + " phi " +
                                    std::to_string(phi) + " vt " + std::to_string(vt);
          const double v_scale = 0.05, w_scale = v_scale / p.eccentricity_m;
          EXPECT_NEAR(got.rotor_vel.x(), ref.rotor_vel.x(), 1e-4 * v_scale) << where;
          EXPECT_NEAR(got.rotor_vel.y(), ref.rotor_vel.y(), 1e-4 * v_scale) << where;
          EXPECT_NEAR(got.stator_vel.x(), ref.stator_vel.x(), 1e-4 * v_scale) << where;
          EXPECT_NEAR(got.stator_vel.y(), ref.stator_vel.y(), 1e-4 * v_scale) << where;
          EXPECT_NEAR(got.spin.speed_rad_per_s, ref.spin.speed_rad_per_s, 1e-4 * w_scale) << where;
          EXPECT_NEAR(geometry(got).normal_velocity_m_per_s, target, 1e-12) << where;
          const double vs_end = geometry(ref).sliding_velocity_m_per_s;
          // The flag the methods start the contact from: the reference's
          // last step was a stick step exactly when the impact ends stuck.
          EXPECT_EQ(ir.sliding_stopped, ended_stuck) << where;
          if (ir.sliding_stopped) {
            EXPECT_NEAR(vs_end, 0.0, 1e-4 * v_scale) << where;
          }
          slid_back += reversed;
          stuck += was_stuck && !reversed && ir.sliding_stopped;
          slid_through += !was_stuck && !reversed;
        }
      }
    }
  }
  // Every branch of the law is met.
  EXPECT_GT(slid_back, 0);
  EXPECT_GT(stuck, 0);
  EXPECT_GT(slid_through, 0);
}

TEST(MotorDrive, ComplianceIsWhatTheAccelerationsAnswer) {
  // The switching method's closed forms use W (model.hpp); the iteration
  // method the accelerations themselves. W must be their derivative with
  // respect to (-F_n, F_t) (exact: they are affine in the forces).
  core::ModelParameters p;
  p.drive_model = core::DriveModel::kMotor;
  p.eccentricity_m = 2e-3;  // a large lever so that W_nt matters
  p.rotor_polar_inertia_kg_m2 = 2e-5;
  const core::JeffcottModel m(p);
  core::Kinematics k;
  k.rotor_pos = core::Vec2(1.5e-3, 1.3e-3);
  k.stator_pos = core::Vec2(1e-4, -0.5e-4);
  k.spin.angle_rad = 0.7;
  k.spin.speed_rad_per_s = 150.0;
  const core::DriveState d = m.drive_at(k, core::DriveState{0.0, 160.0, 70.0, 0.0});
  const core::ContactGeometry g = m.contact_geometry(k, d);
  const core::ContactCompliance w = m.contact_compliance(g, d);
  auto rel = [&](double fn, double ft) {
    const core::Accelerations a = m.accelerations(k, d, g, fn, ft);
    return core::Vec2(g.normal.dot(a.rotor - a.stator), m.sliding_acceleration(k, g, a));
  };
  const core::Vec2 base = rel(0.0, 0.0), by_n = rel(-1.0, 0.0) - base, by_t = rel(0.0, 1.0) - base;
  EXPECT_NEAR(by_n.x(), w.nn, 1e-9 * w.nn);
  EXPECT_NEAR(by_n.y(), w.nt, 1e-9 * w.nn);
  EXPECT_NEAR(by_t.x(), w.nt, 1e-9 * w.nn);
  EXPECT_NEAR(by_t.y(), w.tt, 1e-9 * w.tt);
  EXPECT_GT(std::abs(w.nt), 1e-3 * w.nn);  // the coupling is there to be checked
}

TEST(MotorDrive, PainleveBoundIsAnErrorNamingTheKey) {
  core::Scene s = motor_scene(test::paper_scene());
  s.model.rotor_polar_inertia_kg_m2 = 1e-9;
  try {
    core::validate_scene(s);
    FAIL() << "accepted";
  } catch (const core::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("rotor_polar_inertia_kg_m2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("Painleve"), std::string::npos) << e.what();
  }
}
