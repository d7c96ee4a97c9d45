// The closed forms of steady_response.hpp (derived in docs/steady_response.md)
// against every method: synchronous full annular rub (amplitude, stator
// orbit, normal force) on elastic and rigid stators, low and high friction,
// up to 5x the critical speed; where the closed form has no branch, no
// contact; and the onset of rub on a slow run-up, with and without gravity.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rotor_rub_sim/core/steady_response.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

// rtol 1e-9 on a 2 mm orbit: the rigid methods hold the steady orbit to
// ~1e-11 m (measured); 1e-9 m leaves room across machines.
constexpr double kRigidOrbitTol_m = 1e-9;
constexpr double kRigidForceRelTol = 1e-6;
// Penalty: the rotor overlaps the stator by N / k_c (1e-8 m at k_c 1e9, N 10 N),
// which the rigid closed form leaves out; twice that plus the rigid tolerance.
double penalty_orbit_tol_m(double n_N, double k_c) { return 2.0 * n_N / k_c + kRigidOrbitTol_m; }
constexpr double kPenaltyForceRelTol = 1e-4;  // k_c delta oscillates by ~1e-5 of N (measured)

struct Case {
  const char* name;
  core::StatorModel stator;
  double friction, speed_rad_per_s;
};

// Runs up at the paper's 70 rad/s^2 to the speed, holds it, and returns the
// samples of the last 2 s.
std::vector<core::Sample> hold(const Case& c, const test::Solver& solver, double hold_s = 8.0) {
  const core::Method method = solver.method;
  core::Scene s = test::paper_scene();
  s.model.stator_model = c.stator;
  s.model.friction_coefficient = c.friction;
  s.speed.target_speed_rad_per_s = c.speed_rad_per_s;
  s.speed.max_speed_rad_per_s = std::max(s.speed.max_speed_rad_per_s, c.speed_rad_per_s);
  s.end_time_s = c.speed_rad_per_s / s.speed.acceleration_rad_per_s2 + hold_s;
  s.output_rate_hz = 500.0;
  s.solver.method = method;
  s.solver.integrator = solver.integrator;
  s.solver.rtol = method == core::Method::kPenalty ? 1e-8 : 1e-9;
  s.solver.atol = s.solver.rtol * 1e-3;
  const test::Run r = test::run(s);
  EXPECT_FALSE(r.result.failure.has_value()) << c.name << ": " << r.result.failure->message;
  std::vector<core::Sample> tail;
  for (const auto& x : r.out.samples)
    if (x.t_s > s.end_time_s - 2.0) tail.push_back(x);
  return tail;
}

core::ModelParameters model_of(const Case& c) {
  core::ModelParameters p = test::paper_scene().model;
  p.stator_model = c.stator;
  p.friction_coefficient = c.friction;
  return p;
}

}  // namespace

TEST(SteadyResponse, SynchronousFullRubMatchesTheClosedFormInEveryMethod) {
  const Case cases[] = {
      {"paper, elastic stator, f 0.1, 120 rad/s", core::StatorModel::kElastic, 0.1, 120.0},
      {"elastic stator, high friction f 0.3, 120 rad/s", core::StatorModel::kElastic, 0.3, 120.0},
      {"rigid stator, f 0.1, 400 rad/s (5.2x critical)", core::StatorModel::kRigid, 0.1, 400.0},
      {"rigid stator, f 0.2, 300 rad/s", core::StatorModel::kRigid, 0.2, 300.0},
  };
  for (const auto& c : cases) {
    const auto branch = core::synchronous_full_rub(model_of(c), c.speed_rad_per_s);
    ASSERT_FALSE(branch.empty()) << c.name;
    // The run-up lands on the branch with the larger normal force (the other
    // one is the unstable middle branch of the jump).
    const core::FullRub& fr = branch.front();
    for (const auto& solver : test::all_solvers()) {
      const core::Method method = solver.method;
      // Penalty costs ~0.3 s per simulated second here: one case is enough.
      if (method == core::Method::kPenalty && &c != &cases[0]) continue;
      const auto tail = hold(c, solver);
      ASSERT_FALSE(tail.empty());
      const double tol_m =
          method == core::Method::kPenalty
              ? penalty_orbit_tol_m(fr.normal_force_N, core::ModelParameters{}.contact_stiffness_N_per_m)
              : kRigidOrbitTol_m;
      const double tol_rel = method == core::Method::kPenalty ? kPenaltyForceRelTol : kRigidForceRelTol;
      for (const auto& s : tail) {
        ASSERT_TRUE(s.in_contact) << c.name << " " << solver.name() << " t " << s.t_s;
        EXPECT_FALSE(s.sticking);  // it slides forward at w (C + R_r)
        EXPECT_NEAR(s.kin.rotor_pos.norm(), std::abs(fr.rotor_m), tol_m) << c.name << " " << solver.name();
        EXPECT_NEAR(s.kin.stator_pos.norm(), std::abs(fr.stator_m), tol_m) << c.name << " " << solver.name();
        EXPECT_NEAR(s.normal_force_N, fr.normal_force_N, tol_rel * fr.normal_force_N) << c.name << " " << solver.name();
        // Synchronous: the rotor's phase behind the unbalance is the closed form's.
        const double phase = std::atan2(s.kin.rotor_pos.y(), s.kin.rotor_pos.x()) - s.drive.angle_rad;
        EXPECT_NEAR(std::remainder(phase - std::arg(fr.rotor_m), 2 * M_PI), 0.0, 1e-5) << c.name;
      }
    }
  }
}

// Where the closed form has no synchronous full rub, the run-up does not end in
// contact (it lifts off into the no-contact orbit).
TEST(SteadyResponse, NoBranchNoSustainedContact) {
  const Case cases[] = {
      {"elastic stator, f 0.5, 120 rad/s", core::StatorModel::kElastic, 0.5, 120.0},
      {"rigid stator, f 0.3, 300 rad/s", core::StatorModel::kRigid, 0.3, 300.0},
  };
  for (const auto& c : cases) {
    ASSERT_TRUE(core::synchronous_full_rub(model_of(c), c.speed_rad_per_s).empty()) << c.name;
    for (const auto& solver : test::rigid_solvers()) {
      const auto tail = hold(c, solver);
      for (const auto& s : tail) ASSERT_FALSE(s.in_contact) << c.name << " " << solver.name();
      // ... and runs on the unbalance response.
      const double z = std::abs(core::unbalance_response_m(model_of(c), c.speed_rad_per_s));
      EXPECT_NEAR(tail.back().kin.rotor_pos.norm(), z, 1e-6) << c.name;
    }
  }
}

// On a slow run-up the first contact comes at the speed where the steady
// unbalance orbit (plus the gravity sags' offset) reaches the clearance,
// late by the response's lag behind the sweep: measured 0.034 rad/s at
// 0.5 rad/s^2 and 0.0066 at 0.1 (it scales with the sweep rate).
// With gravity the orbit first grazes the stator at the tangency, where the
// pressing force only just changes sign: switching used to miss the re-touch
// after such a graze and failed the run (invariant_violated, 5e-9 m beyond the
// bore at rtol 1e-8); this test keeps that case.
constexpr double kSweepLag_rad_per_s = 0.1;

TEST(SteadyResponse, RubOnsetOnASlowRunUp) {
  for (const double g : {0.0, 9.81}) {
    for (const auto& solver : test::rigid_solvers()) {
      const core::Method method = solver.method;
      core::Scene s = test::paper_scene();
      s.model.gravity_m_per_s2 = g;
      const double onset = core::rub_onset_speed_rad_per_s(s.model);
      ASSERT_TRUE(std::isfinite(onset));
      s.speed.acceleration_rad_per_s2 = 0.5;
      s.speed.target_speed_rad_per_s = onset + 5.0;
      s.end_time_s = s.speed.target_speed_rad_per_s / 0.5;
      s.solver.method = method;
      s.solver.integrator = solver.integrator;
      s.solver.rtol = 1e-8;
      s.solver.atol = 1e-11;
      const test::Run r = test::run(s);
      ASSERT_FALSE(r.result.failure.has_value())
          << "g " << g << " " << solver.name() << " " << r.result.failure->message;
      // Released at the centre under gravity, the rotor drops onto the
      // stator once (a graze at 0.025 s) and then settles on its sag; the
      // onset is the first contact after that transient (decayed by 1e-6
      // after 10 s).
      double t_contact = std::nan("");
      for (const auto& e : r.out.events) {
        if (e.t_s > 10.0) {
          t_contact = e.t_s;
          break;
        }
      }
      ASSERT_TRUE(std::isfinite(t_contact)) << "g " << g;
      const double w_contact = t_contact * 0.5;
      EXPECT_GT(w_contact, onset) << "g " << g << " " << solver.name();
      EXPECT_LT(w_contact, onset + kSweepLag_rad_per_s) << "g " << g << " " << solver.name();
    }
  }
  // The paper rotor without gravity: 70.643 rad/s (0.915 of the critical speed).
  EXPECT_NEAR(core::rub_onset_speed_rad_per_s(test::paper_scene().model), 70.6434, 1e-4);
}

// The onset speed solves its equation |z(w)| = C - |sag_rotor - sag_stator|
// below the amplitude's peak, with gravity on elastic and rigid stators, at
// the values a bisection of the same equation gives independently, and
// gives its stated answers where there is no root.
TEST(SteadyResponse, RubOnsetSpeedSolvesItsEquation) {
  // TOMS 748 to 50 bits brackets w within 2^-49 of itself; |z| moves by
  // d ln|z| / d ln w (12 here) times that: 1e-14 of the reach.
  constexpr double kOnsetReachRelTol = 1e-12;
  // The onsets with gravity, from a bisection of |z(w)| = reach in Python
  // (reach 0.576 mm on the elastic stator, 0.355 mm on the rigid one).
  constexpr double kElasticOnset_rad_per_s = 59.36713, kRigidOnset_rad_per_s = 52.98131;
  constexpr double kOnsetTol_rad_per_s = 1e-5;  // the reference's printed digits
  const double g = 9.81;
  for (const core::StatorModel stator : {core::StatorModel::kElastic, core::StatorModel::kRigid}) {
    for (const double gravity : {0.0, g}) {
      core::ModelParameters p = test::paper_scene().model;
      p.stator_model = stator;
      p.gravity_m_per_s2 = gravity;
      const double sag_rotor = gravity * p.rotor_mass_kg / p.rotor_stiffness_N_per_m;
      const double sag_stator =
          stator == core::StatorModel::kRigid ? 0.0 : gravity * p.stator_mass_kg / p.stator_stiffness_N_per_m;
      const double reach = p.clearance_m - std::abs(sag_rotor - sag_stator);
      const double w = core::rub_onset_speed_rad_per_s(p);
      SCOPED_TRACE(std::string(core::to_string(stator)) + (gravity > 0.0 ? ", gravity" : ""));
      const double wn = std::sqrt(p.rotor_stiffness_N_per_m / p.rotor_mass_kg);
      EXPECT_GT(w, 0.0);
      EXPECT_LT(w, wn) << "below the critical speed on this lightly damped rotor";
      EXPECT_NEAR(std::abs(core::unbalance_response_m(p, w)), reach, kOnsetReachRelTol * reach);
      if (gravity > 0.0) {
        EXPECT_NEAR(w, stator == core::StatorModel::kRigid ? kRigidOnset_rad_per_s : kElasticOnset_rad_per_s,
                    kOnsetTol_rad_per_s);
      }
    }
  }
  core::ModelParameters p = test::paper_scene().model;
  p.gravity_m_per_s2 = g;
  p.clearance_m = 0.5 * p.rotor_mass_kg * g / p.rotor_stiffness_N_per_m;  // sags onto the stator
  p.stator_model = core::StatorModel::kRigid;
  EXPECT_EQ(core::rub_onset_speed_rad_per_s(p), 0.0) << "in contact at rest";
  p = test::paper_scene().model;
  p.rotor_damping_N_s_per_m = 40.0;  // zeta 0.62: the orbit's peak (0.41 mm) stays under the clearance
  EXPECT_TRUE(std::isinf(core::rub_onset_speed_rad_per_s(p)));
  p.rotor_damping_N_s_per_m = 60.0;  // zeta 0.93: no peak, the orbit rises towards e = 0.4 mm
  EXPECT_TRUE(std::isinf(core::rub_onset_speed_rad_per_s(p)));
  p = test::paper_scene().model;
  p.gravity_m_per_s2 = g;
  p.rotor_stiffness_N_per_m = 0.0;
  EXPECT_TRUE(std::isnan(core::rub_onset_speed_rad_per_s(p))) << "no static position";
}
