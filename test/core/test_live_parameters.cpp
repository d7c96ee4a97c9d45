// Live parameter changes (Simulation::change_parameters): a change applies
// from its instant on and not before, in every method; what it leads to is
// checked against closed forms (the unbalance response after a blade loss,
// the synchronous full rub after a friction and an unbalance-phase change),
// a contact whose bore moves away lifts off at the change, and a refused
// change names its key and reason and changes nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <map>
#include <string>
#include <utility>

#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/steady_response.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

class LiveChange : public ::testing::TestWithParam<test::Solver> {};

// The paper's run-up to 3.2 s: free flight until the first graze at
// 1.113 s (the resonance), rub from there on and off.
core::Scene runup(const test::Solver& solver) {
  core::Scene s = test::with_method(test::paper_scene(), solver, 1e-8, 1e-11);
  s.end_time_s = 3.2;
  return s;
}

// Runs sim to t_s, collecting into out.
void advance(core::Simulation& sim, double t_s, test::Collect& out) {
  ASSERT_TRUE(sim.advance_to(t_s, out)) << sim.failure()->message;
}

double max_distance_m(const std::vector<core::Sample>& a, const std::vector<core::Sample>& b, double from_s) {
  double worst = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    if (a[i].t_s >= from_s) worst = std::max(worst, (a[i].kin.rotor_pos - b[i].kin.rotor_pos).norm());
  }
  return worst;
}

}  // namespace

// Friction and restitution changed at 1.0 s, in free flight: nothing before
// 1.0 s moves (bit for bit), the rub from 1.113 s on does, and the run is
// the one that had the new values from the start (they act in contact
// only), to the integration's error.
TEST_P(LiveChange, AppliesFromItsInstantAndNotBefore) {
  const core::Scene s = runup(GetParam());
  test::Collect base_out, changed_out, fresh_out;
  core::Simulation base(s), changed(s);
  advance(base, s.end_time_s, base_out);
  advance(changed, 1.0, changed_out);
  changed.change_parameters({{"friction_coefficient", "0.3"}, {"restitution", "0.5"}});
  EXPECT_EQ(changed.scene().model.friction_coefficient, 0.3);
  advance(changed, s.end_time_s, changed_out);
  core::Scene fresh_scene = s;
  fresh_scene.model.friction_coefficient = 0.3;
  fresh_scene.model.restitution = 0.5;
  core::Simulation fresh(fresh_scene);
  advance(fresh, s.end_time_s, fresh_out);

  ASSERT_EQ(base_out.samples.size(), changed_out.samples.size());
  for (std::size_t i = 0; i < base_out.samples.size() && base_out.samples[i].t_s <= 1.0; ++i) {
    ASSERT_EQ(base_out.samples[i].kin.rotor_pos, changed_out.samples[i].kin.rotor_pos)
        << "t " << base_out.samples[i].t_s;
  }
  // The rub with f 0.3 and e 0.5 against f 0.1 and e 0: orbits apart by
  // a good part of the clearance (2 mm) within 0.4 s of rub.
  EXPECT_GT(max_distance_m(base_out.samples, changed_out.samples, 1.0), 1e-4);
  // The restart at 1.0 s only changes the steps: at rtol 1e-8 the runs
  // agree to 6e-12 m on switching dop853 (measured); 1e-9 m bounds it on
  // every solver with room for the impacts' amplification.
  EXPECT_LT(max_distance_m(fresh_out.samples, changed_out.samples, 1.0), 1e-9);
}

// A clearance opened while the rotor rubs: a lift-off exactly at the
// change, then free flight; one closed on the rotor is refused and the run
// goes on as if it had not been asked.
TEST_P(LiveChange, ClearanceOpenedInContactLiftsOffThereAndOneClosedOnTheRotorIsRefused) {
  core::Scene s = runup(GetParam());
  s.end_time_s = 3.0;
  core::Simulation sim(s), base(s);
  test::Collect out, base_out;
  // Into the rub until a sample in contact, after the first touchdown.
  double t = 2.8;
  advance(sim, t, out);
  while (!out.samples.back().in_contact && t < 2.95) advance(sim, t += 1e-3, out);
  ASSERT_TRUE(out.samples.back().in_contact) << "no contact sample by 2.95 s";
  advance(base, t, base_out);

  const double distance_m = (out.samples.back().kin.rotor_pos - out.samples.back().kin.stator_pos).norm();
  try {
    sim.change_parameters({{"clearance_m", std::to_string(distance_m - 1e-5)}});
    ADD_FAILURE() << "a clearance below the rotor-stator distance was accepted";
  } catch (const core::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("clearance_m"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("overlap"), std::string::npos) << e.what();
  }
  advance(sim, t + 0.01, out);
  advance(base, t + 0.01, base_out);
  EXPECT_EQ(out.samples.back().kin.rotor_pos, base_out.samples.back().kin.rotor_pos) << "the refusal changed the run";

  // Back into contact (the rub is intermittent), then the clearance opened.
  while (!out.samples.back().in_contact && sim.time() < 2.99) advance(sim, sim.time() + 1e-3, out);
  ASSERT_TRUE(out.samples.back().in_contact) << "no contact sample by 2.99 s";
  const std::size_t events_before = out.events.size();
  const double t_change = sim.time();
  sim.change_parameters({{"clearance_m", "2.5e-3"}});
  advance(sim, s.end_time_s, out);
  // The first event after the change is the lift-off it makes, at its instant.
  ASSERT_GT(out.events.size(), events_before);
  const core::ContactEvent& first = out.events[events_before];
  EXPECT_EQ(first.kind, core::EventKind::kLiftoff);
  EXPECT_EQ(first.t_s, t_change);
  for (const auto& x : out.samples) {
    if (x.t_s > t_change) {
      ASSERT_FALSE(x.in_contact) << "t " << x.t_s;  // 0.5 mm more room than the orbit needs
    }
  }
}

// Two runs given the same changes at the same instants are the same run,
// bit for bit, however they are advanced: one in 1 ms chunks (as the node
// at a slow pace), one in a single call per stretch (as at full speed).
// The node's replay promise rests on it.
TEST_P(LiveChange, SameChangesSameRunInAnyChunks) {
  const core::Scene s = runup(GetParam());
  test::Collect a_out, b_out;
  core::Simulation a(s), b(s);
  // The node's chunks: ends on the 1 ms grid, k / 1000 exactly.
  auto chunked = [&](double until) {
    for (long k = std::lround(a.time() * 1e3) + 1; k <= std::lround(until * 1e3); ++k) {
      advance(a, static_cast<double>(k) / 1e3, a_out);
    }
  };
  chunked(2.85);
  advance(b, 2.85, b_out);
  for (auto* sim : {&a, &b}) sim->change_parameters({{"eccentricity_m", "0.6e-3"}, {"unbalance_phase_rad", "1.0"}});
  chunked(2.9);
  advance(b, 2.9, b_out);
  for (auto* sim : {&a, &b}) sim->change_parameters({{"friction_coefficient", "0.2"}});
  chunked(s.end_time_s);
  advance(b, s.end_time_s, b_out);
  ASSERT_EQ(a_out.samples.size(), b_out.samples.size());
  for (std::size_t i = 0; i < a_out.samples.size(); ++i) {
    ASSERT_EQ(a_out.samples[i].kin.rotor_pos, b_out.samples[i].kin.rotor_pos) << "t " << a_out.samples[i].t_s;
  }
  ASSERT_EQ(a_out.events.size(), b_out.events.size());
}

// A node that runs past the scene's end (end_action continue: the end moved
// to infinity) still takes live changes.
TEST_P(LiveChange, AfterTheEndWasMovedToInfinity) {
  core::Scene s = runup(GetParam());
  s.end_time_s = 0.1;
  core::Simulation sim(s);
  sim.set_end_time(std::numeric_limits<double>::infinity());
  test::Collect out;
  advance(sim, 0.2, out);
  sim.change_parameters({{"friction_coefficient", "0.3"}});
  EXPECT_EQ(sim.scene().model.friction_coefficient, 0.3);
  advance(sim, 0.3, out);
}

// Blade loss in free flight at a constant 150 rad/s (twice the critical
// speed), a large clearance: the unbalance jumps from 0.4 mm at 0 rad to
// 0.7 mm at 2 rad; once the transient has decayed (damping 30 N s/m,
// zeta 0.46: e^-35 after 1 s), the orbit is the closed form's
// m e w^2 e^(i beta) / (k - m w^2 + i c w) turning with the spin.
TEST_P(LiveChange, BladeLossSettlesOnTheNewUnbalanceResponse) {
  core::Scene s = test::with_method(test::paper_scene(), GetParam(), 1e-10, 1e-13);
  s.model.clearance_m = 5e-3;
  s.model.rotor_damping_N_s_per_m = 30.0;
  s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = 150.0;
  s.end_time_s = 2.5;
  core::Simulation sim(s);
  test::Collect out;
  advance(sim, 1.0, out);
  sim.change_parameters({{"eccentricity_m", "0.7e-3"}, {"unbalance_phase_rad", "2.0"}});
  advance(sim, s.end_time_s, out);
  core::ModelParameters after = s.model;
  after.eccentricity_m = 0.7e-3;
  after.unbalance_phase_rad = 2.0;
  const std::complex<double> z = core::unbalance_response_m(after, 150.0);
  ASSERT_GT(std::abs(z), 5e-4);
  for (const auto& x : out.samples) {
    if (x.t_s < 2.0) continue;
    const std::complex<double> expected = z * std::polar(1.0, x.drive.angle_rad);
    // rtol 1e-10 on a 0.8 mm orbit: 1e-12 m of error; 1e-10 m leaves room.
    EXPECT_NEAR(x.kin.rotor_pos.x(), expected.real(), 1e-10) << "t " << x.t_s;
    EXPECT_NEAR(x.kin.rotor_pos.y(), expected.imag(), 1e-10) << "t " << x.t_s;
  }
}

// A motor drive's spin (angle, speed, the controller's integrator) and a
// rigid stator's frame carry over a restart: friction changed in free flight
// on the motor-driven run-up, and a rigid stator's offset moved while the
// rotor flies free, give the runs that had those values from the start (the
// offset of a rigid stator acts on contact only; the rotor's spring centre is
// the casing's), to the integration's error.
TEST_P(LiveChange, MotorSpinAndRigidStatorFrameCarryOver) {
  core::Scene motor =
      test::with_method(core::load_scene(test::source_path("config/machine_runup.yaml")), GetParam(), 1e-8, 1e-11);
  motor.end_time_s = 1.3;  // first contact at 1.113 s
  core::Scene rigid = test::with_method(test::paper_scene(), GetParam(), 1e-8, 1e-11);
  rigid.model.stator_model = core::StatorModel::kRigid;
  rigid.model.clearance_m = 5e-3;  // no contact
  rigid.end_time_s = 1.3;
  const std::pair<core::Scene, std::map<std::string, std::string>> cases[] = {
      {motor, {{"friction_coefficient", "0.3"}}}, {rigid, {{"stator_offset_x_m", "1e-3"}}}};
  for (const auto& [scene, change] : cases) {
    core::Simulation changed(scene);
    test::Collect changed_out, fresh_out;
    advance(changed, 1.0, changed_out);
    changed.change_parameters(change);
    advance(changed, scene.end_time_s, changed_out);
    core::Scene fresh_scene = scene;
    for (const auto& [key, value] : change) core::set_scene_value(fresh_scene, key, value);
    core::Simulation fresh(fresh_scene);
    advance(fresh, scene.end_time_s, fresh_out);
    // As AppliesFromItsInstantAndNotBefore: 1e-9 m bounds the restart's effect.
    EXPECT_LT(max_distance_m(fresh_out.samples, changed_out.samples, 1.0), 1e-9) << change.begin()->first;
    // The spin: rtol 1e-8 of ~90 rad/s.
    EXPECT_NEAR(changed_out.samples.back().drive.speed_rad_per_s, fresh_out.samples.back().drive.speed_rad_per_s, 1e-6);
  }
}

// Support loosening under gravity, beyond the paper's vertical machine: a
// rotor at rest (no spin, no unbalance) hangs on its shaft at the sag
// m g / k (1.64 mm, inside the 2 mm clearance of a rigid bore); its shaft
// stiffness falls to k' at 1 s, the new sag (2.73 mm) lies beyond the bore,
// and it comes to rest on the bore's bottom, pressed by N = m g - k' C.
// Critically damped before (zeta 1: at rest to e^-77 by 1 s); after the
// change the rotor falls onto the bore, where the plastic touchdown straight
// down ends its motion (no sliding: it stays at x = 0).
TEST_P(LiveChange, SupportLooseningUnderGravityRestsOnTheBore) {
  core::Scene s = test::with_method(test::paper_scene(), GetParam(), 1e-10, 1e-13);
  s.model.stator_model = core::StatorModel::kRigid;
  s.model.gravity_m_per_s2 = 9.81;
  s.model.eccentricity_m = 0.0;
  s.model.restitution = 0.0;
  const double m = s.model.rotor_mass_kg, k = s.model.rotor_stiffness_N_per_m, C = s.model.clearance_m;
  s.model.rotor_damping_N_s_per_m = 2.0 * std::sqrt(k * m);
  s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = 0.0;
  s.end_time_s = 2.0;
  core::Simulation sim(s);
  test::Collect before, after;
  advance(sim, 1.0, before);
  // Hanging at the sag (rtol 1e-10 of a 1.6 mm position: 1e-12 m; 1e-10 m leaves room).
  EXPECT_NEAR(before.samples.back().kin.rotor_pos.y(), -m * 9.81 / k, 1e-10);
  EXPECT_FALSE(before.samples.back().in_contact);
  const double k_loose = 1500.0;
  sim.change_parameters({{"rotor_stiffness_N_per_m", core::exact_text(k_loose)}});
  advance(sim, s.end_time_s, after);
  const core::Sample& rest = after.samples.back();
  // The penalty method rests p = N / k_c beyond the bore, where the shaft
  // pulls k' p more: N = (m g - k' C) / (1 + k' / k_c), 1.5e-6 below the
  // rigid contact's.
  const bool penalty = GetParam().method == core::Method::kPenalty;
  const double k_c = s.model.contact_stiffness_N_per_m;
  const double n = (m * 9.81 - k_loose * C) / (penalty ? 1.0 + k_loose / k_c : 1.0);  // 1.10 N
  ASSERT_TRUE(rest.in_contact);
  // Rigid methods: the constraint force from positions held to atol, times
  // k' (1e-10 N); the penalty's spring turns the position's tolerance into
  // force, k_c atol = 1e-4 N (measured 6e-9 N).
  EXPECT_NEAR(rest.normal_force_N, n, penalty ? k_c * s.solver.atol : 1e-9 * n);
  EXPECT_NEAR(rest.kin.rotor_pos.y(), -C - (penalty ? n / k_c : 0.0), 1e-10);
  EXPECT_NEAR(rest.kin.rotor_pos.x(), 0.0, 1e-10);
}

INSTANTIATE_TEST_SUITE_P(AllSolvers, LiveChange, ::testing::ValuesIn(test::all_solvers()),
                         [](const auto& info) { return info.param.name(); });

// Synchronous full rub on a rigid stator at 300 rad/s (test_steady_response's
// case), then the friction lowered from 0.2 to 0.1 and the unbalance turned
// by 1 rad on the shaft: the rub settles on the closed form's branch with
// the new values (the larger normal force, as a run-up lands), its phase
// turned with the unbalance.
TEST(LiveChangeClosedForm, FullRubSettlesOnTheNewBranch) {
  for (const auto& solver : test::rigid_solvers()) {
    core::Scene s = test::with_method(test::paper_scene(), solver, 1e-9, 1e-12);
    s.model.stator_model = core::StatorModel::kRigid;
    s.model.friction_coefficient = 0.2;
    s.speed.target_speed_rad_per_s = 300.0;
    s.end_time_s = 300.0 / s.speed.acceleration_rad_per_s2 + 12.0;
    s.output_rate_hz = 500.0;
    core::Simulation sim(s);
    test::Collect out;
    advance(sim, s.end_time_s - 8.0, out);
    ASSERT_TRUE(out.samples.back().in_contact) << solver.name();
    sim.change_parameters({{"friction_coefficient", "0.1"}, {"unbalance_phase_rad", "1.0"}});
    advance(sim, s.end_time_s, out);
    core::ModelParameters after = s.model;
    after.friction_coefficient = 0.1;
    after.unbalance_phase_rad = 1.0;
    const auto branch = core::synchronous_full_rub(after, 300.0);
    ASSERT_FALSE(branch.empty());
    const core::FullRub& fr = branch.front();
    for (const auto& x : out.samples) {
      if (x.t_s < s.end_time_s - 2.0) continue;
      ASSERT_TRUE(x.in_contact) << solver.name() << " t " << x.t_s;
      // test_steady_response's tolerances, for the same reasons.
      EXPECT_NEAR(x.kin.rotor_pos.norm(), std::abs(fr.rotor_m), 1e-9) << solver.name();
      EXPECT_NEAR(x.normal_force_N, fr.normal_force_N, 1e-6 * fr.normal_force_N) << solver.name();
      const double phase = std::atan2(x.kin.rotor_pos.y(), x.kin.rotor_pos.x()) - x.drive.angle_rad;
      EXPECT_NEAR(std::remainder(phase - std::arg(fr.rotor_m), 2 * M_PI), 0.0, 1e-5) << solver.name();
    }
  }
}

// What cannot change, or not to that value, is refused with the key, the
// value or the reason, and nothing changes: not even the keys of the same
// request that were fine.
TEST(LiveChangeRefusals, NameTheKeyAndTheReasonAndChangeNothing) {
  core::Scene s = test::paper_scene();
  s.end_time_s = 0.5;
  core::Simulation sim(s);
  test::Collect out;
  advance(sim, 0.1, out);
  auto refusal = [&](const std::map<std::string, std::string>& changes) -> std::string {
    try {
      sim.change_parameters(changes);
    } catch (const core::SceneError& e) {
      return e.what();
    }
    return "accepted";
  };
  auto contains = [](const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; };
  const std::string structural = refusal({{"stator_model", "rigid"}});
  EXPECT_TRUE(contains(structural, "'stator_model' cannot change while running")) << structural;
  EXPECT_TRUE(contains(refusal({{"method", "penalty"}}), "numerics")) << refusal({{"method", "penalty"}});
  EXPECT_TRUE(contains(refusal({{"rotor_mass_kg", "0.5"}}), "unbalance")) << refusal({{"rotor_mass_kg", "0.5"}});
  EXPECT_TRUE(contains(refusal({{"friction_coeficient", "0.2"}}), "did you mean 'friction_coefficient'"));
  const std::string range = refusal({{"friction_coefficient", "3"}});
  EXPECT_TRUE(contains(range, "'friction_coefficient': value 3 is out of range; accepted: [0, 2]")) << range;
  EXPECT_TRUE(contains(refusal({{"restitution", "nan"}}), "not a finite number")) << refusal({{"restitution", "nan"}});
  EXPECT_TRUE(contains(refusal({{"contact_stiffness_N_per_m", "1e8"}}), "penalty method only"));
  EXPECT_TRUE(contains(refusal({{"drive_torque_limit_N_m", "1"}}), "drive_model motor only"));
  // A rule between keys: the stator's offset must stay below the clearance.
  EXPECT_TRUE(contains(refusal({{"stator_offset_x_m", "3e-3"}}), "below clearance_m"));
  // All or nothing: the good key of a refused request is not applied.
  EXPECT_TRUE(contains(refusal({{"friction_coefficient", "0.3"}, {"restitution", "2"}}), "'restitution'"));
  EXPECT_EQ(sim.scene().model.friction_coefficient, s.model.friction_coefficient);
  EXPECT_EQ(sim.scene().model.stator_model, core::StatorModel::kElastic);
  EXPECT_EQ(sim.time(), 0.1);
  // And the run goes on as one that was never asked.
  core::Simulation base(s);
  test::Collect base_out;
  advance(base, s.end_time_s, base_out);
  advance(sim, s.end_time_s, out);
  ASSERT_EQ(out.samples.size(), base_out.samples.size());
  EXPECT_EQ(out.samples.back().kin.rotor_pos, base_out.samples.back().kin.rotor_pos);
}

// The key table says which keys are live, with bounds for the
// dynamic_reconfigure server, and why the others are not.
TEST(LiveChangeRefusals, EveryKeyIsLiveOrSaysWhyNot) {
  int live = 0;
  for (const auto& k : core::scene_keys()) {
    if (k.live) {
      ++live;
      EXPECT_FALSE(std::isnan(k.min_value)) << k.key;
      EXPECT_LT(k.min_value, k.max_value) << k.key;
    } else {
      EXPECT_FALSE(k.live_refusal.empty()) << k.key;
    }
  }
  EXPECT_EQ(live, 17);
}
