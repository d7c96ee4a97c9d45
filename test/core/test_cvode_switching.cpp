// The CVODE contender (tools/cvode_switching.hpp) against the core's
// switching method: the same model, contact law and events on another
// integrator, so at tight tolerances both follow the same trajectory.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "cvode_switching.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "rotor_rub_sim/core/trajectory_compare.hpp"

namespace {

using namespace rotor_rub;

constexpr double kErrorRate_hz = 10000.0;

// Agreement of the rotor positions at 10 kHz, the contender at rtol 1e-8 /
// atol 1e-11 against the core at rtol 1e-10 / atol 1e-13 (whose own error is
// 2.2e-11 m on the paper scene, against rtol 1e-12: the differences are
// CVODE's global error). The impacts amplify any difference, rounding
// included: measured over 20 rounding-level variants of each scene (masses
// scaled by 1 + k 1e-12, k = 0..19; two versions of the core's contact
// dynamics that differ only in rounding), max |r_r - r_r,core|:
//   paper run-up:                     Adams 1.0e-8 .. 6.3e-8 m (median 2.3e-8),
//                                     BDF   9.9e-8 .. 2.8e-7 m (median 1.5e-7)
//   rigid, f 0.3, e 0.5, drive break: Adams 1.1e-8 m, BDF 3.1e-8 m (all variants)
// Set about 3x above the largest. At the same rtol CVODE errs 10x (Adams) to
// 75x (BDF) more than the core (2.0e-9 m at rtol 1e-8): it controls each
// step's local error in the RMS norm over the state (up to sqrt(n) times the
// max norm of the core's dopri5), without dopri5's local extrapolation, and
// BDF's error constants are the larger.
constexpr double kAdamsAgreement_m = 2e-7;
constexpr double kBdfAgreement_m = 1e-6;
// Rolling: the impacts before the rotor rolls (14 grazes, 6 touchdowns)
// amplify a state difference from 3e-10 m at 0.15 s to 8e-8 m at 0.3 s, and
// the slip-to-stick transition 10x more (8.4e-7 m from 0.305 s on, where
// rolling holds it; the same in all 20 variants); the core itself at rtol
// 1e-8 shows the same profile against its rtol 1e-10 run (6.2e-8, then
// 6.6e-7 m). Set 5x above the measured 8.4e-7 m.
constexpr double kRollingAgreement_m = 4e-6;
// The flexible rotor's seal rub (below): its stiff modes hold both
// integrators' steps below what the tolerance asks (stability, not
// accuracy: 68286 Adams steps at rtol 1e-8 on the example), so they agree
// far closer than on the Jeffcott. Measured max |r_r - r_r,core| 6.2e-11 m
// (the example) and 3.2e-11 m (elastic stator, rebounds), the probes 3.5e-11
// and 2.5e-11 m. Set 5x above the largest.
constexpr double kFlexibleAgreement_m = 3.1e-10;
// First contact: measured up to 1.6e-8 s (Adams), 1.2e-7 s (BDF).
constexpr double kFirstContactAgreement_s = 1e-6;

core::Scene paper_scene() { return core::load_scene(std::string(ROTOR_RUB_SOURCE_DIR) + "/config/paper_runup.yaml"); }

// Not the paper's: a rigid stator, friction 0.3, rebounds (restitution 0.5)
// and the drive's segment break inside the run (the ramp ends at 2 s).
core::Scene rigid_rebound_scene() {
  core::Scene s = paper_scene();
  s.model.stator_model = core::StatorModel::kRigid;
  s.model.friction_coefficient = 0.3;
  s.model.restitution = 0.5;
  s.speed.acceleration_rad_per_s2 = 140.0;
  return s;
}

// Constant 600 rad/s, friction 0.3: grazes and impacts, then the rotor rolls
// (stick) from 0.305 s on.
core::Scene rolling_scene() {
  core::Scene s = paper_scene();
  s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = 600.0;
  s.model.friction_coefficient = 0.3;
  s.end_time_s = 0.5;
  return s;
}

struct Collect : core::SimulationObserver {
  std::vector<core::Sample> samples;
  std::vector<core::ContactEvent> events;
  void on_sample(const core::Sample& s) override { samples.push_back(s); }
  void on_event(const core::ContactEvent& e) override { events.push_back(e); }
};

Collect core_reference(core::Scene s) {
  s.solver.method = core::Method::kSwitching;
  s.solver.rtol = 1e-10;
  s.solver.atol = 1e-13;
  s.output_rate_hz = kErrorRate_hz;
  Collect out;
  const core::RunResult r = core::run_scene(s, out);
  EXPECT_FALSE(r.failure.has_value()) << r.failure->message;
  return out;
}

tools::CvodeRun contender(core::Scene s, bool adams) {
  s.solver.rtol = 1e-8;
  s.solver.atol = 1e-11;
  tools::CvodeOptions options;
  options.adams = adams;
  tools::CvodeRun run = tools::run_cvode_switching(s, kErrorRate_hz, options);
  EXPECT_FALSE(run.failure.has_value()) << *run.failure;
  return run;
}

long count(const std::vector<core::ContactEvent>& events, core::EventKind kind) {
  long n = 0;
  for (const auto& e : events) n += e.kind == kind;
  return n;
}

// The events that change the state: without the grazes that touch at zero
// normal velocity (no impulse, the flight goes on unchanged). The core logs
// one now and then at the instant of a lift-off, where the gap starts at a
// tangency and its sign is rounding (2 of the 20 rolling variants at rtol
// 1e-10); the contender arms the gap only below its noise floor.
std::vector<core::ContactEvent> state_changing(const std::vector<core::ContactEvent>& events) {
  std::vector<core::ContactEvent> kept;
  for (const auto& e : events) {
    if (e.kind != core::EventKind::kGraze || e.impulse_N_s > 0.0) kept.push_back(e);
  }
  return kept;
}

void expect_same_event_kinds(const std::vector<core::ContactEvent>& run, const std::vector<core::ContactEvent>& ref) {
  const auto a = state_changing(run), b = state_changing(ref);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < b.size(); ++i) EXPECT_EQ(a[i].kind, b[i].kind) << i << " at " << b[i].t_s << " s";
}

long sticking(const std::vector<core::Sample>& samples) {
  long n = 0;
  for (const auto& s : samples) n += s.sticking;
  return n;
}

// The rotor positions and the first contact agree; returns the contender's run.
tools::CvodeRun expect_agreement(const core::Scene& scene, const Collect& ref, bool adams, double tolerance_m) {
  const tools::CvodeRun run = contender(scene, adams);
  EXPECT_EQ(run.samples.size(), ref.samples.size());
  const core::TrajectoryError e = core::compare_trajectories(run.samples, ref.samples);
  std::printf("%s: max rotor difference %.3g m (stator %.3g m), first contact %.3g s; %ld steps, %ld RHS\n",
              adams ? "Adams" : "BDF", e.max_rotor_m, e.max_stator_m,
              core::first_contact_s(run.events_found) - core::first_contact_s(ref.events), run.steps, run.rhs_evals);
  EXPECT_LT(e.max_rotor_m, tolerance_m);
  EXPECT_NEAR(core::first_contact_s(run.events_found), core::first_contact_s(ref.events), kFirstContactAgreement_s);
  // Sustained contacts are the same; grazes may not be: a rebound settles
  // when its apex would stay below atol (contact_law.hpp), so their number
  // depends on the run's atol.
  EXPECT_EQ(count(run.events_found, core::EventKind::kTouchdown), count(ref.events, core::EventKind::kTouchdown));
  EXPECT_EQ(count(run.events_found, core::EventKind::kLiftoff), count(ref.events, core::EventKind::kLiftoff));
  return run;
}

TEST(CvodeSwitching, PaperRunupAgreesWithCoreSwitching) {
  const core::Scene s = paper_scene();
  const Collect ref = core_reference(s);
  for (bool adams : {true, false}) {
    const tools::CvodeRun run = expect_agreement(s, ref, adams, adams ? kAdamsAgreement_m : kBdfAgreement_m);
    // Plastic impacts (no rebound to settle): every event is the reference's.
    expect_same_event_kinds(run.events_found, ref.events);
    // One restart per event, and the start (the ramp ends at end_time_s).
    EXPECT_EQ(run.reinits, run.events + 1);
  }
}

TEST(CvodeSwitching, RigidStatorWithReboundsAndADriveBreakAgrees) {
  const core::Scene s = rigid_rebound_scene();
  const Collect ref = core_reference(s);
  ASSERT_GT(count(ref.events, core::EventKind::kGraze), 5);  // rebounds
  for (bool adams : {true, false}) {
    const tools::CvodeRun run = expect_agreement(s, ref, adams, adams ? kAdamsAgreement_m : kBdfAgreement_m);
    // The start, every event, and the end of the ramp at 2 s.
    EXPECT_EQ(run.reinits, run.events + 2);
  }
}

TEST(CvodeSwitching, RollingStartsWhereCoreSwitchingRolls) {
  const core::Scene s = rolling_scene();
  const Collect ref = core_reference(s);
  const tools::CvodeRun run = expect_agreement(s, ref, true, kRollingAgreement_m);
  expect_same_event_kinds(run.events_found, ref.events);
  // One friction transition (slip to stick).
  EXPECT_EQ(run.events - static_cast<long>(run.events_found.size()), 1);
  EXPECT_GT(sticking(ref.samples), 1000);
  // The same samples rolling, but one: the stick onsets agree to ~1e-7 s,
  // which may move one 1e-4 s sample across it on another build.
  EXPECT_NEAR(sticking(run.samples), sticking(ref.samples), 1);
}

TEST(CvodeSwitching, SamplesDoNotChangeTheIntegration) {
  // The benchmark times runs without samples and measures the error on a
  // sampled one: the dense output must leave the steps alone.
  const core::Scene s = paper_scene();
  const tools::CvodeRun timed = tools::run_cvode_switching(s, 0.0);
  const tools::CvodeRun sampled = tools::run_cvode_switching(s, kErrorRate_hz);
  ASSERT_FALSE(timed.failure.has_value()) << *timed.failure;
  EXPECT_TRUE(timed.samples.empty());
  EXPECT_EQ(sampled.samples.size(), static_cast<std::size_t>(s.end_time_s * kErrorRate_hz) + 1);
  EXPECT_EQ(sampled.samples.back().t_s, s.end_time_s);
  EXPECT_EQ(timed.steps, sampled.steps);
  EXPECT_EQ(timed.rhs_evals, sampled.rhs_evals);
  EXPECT_EQ(timed.events_found.size(), sampled.events_found.size());
  EXPECT_GT(timed.wall_time_s, 0.0);
}

// A flexible rotor (config/seal_rub_runup.yaml: 8 planar modes, the rub at a
// seal between two disks, the probes at a bearing), through its first
// contact, the sustained rub and its end; and, beyond the example, an
// elastic stator with rebounds (restitution 0.5, friction 0.4).
core::Scene seal_scene() {
  core::Scene s = core::load_scene(std::string(ROTOR_RUB_SOURCE_DIR) + "/config/seal_rub_runup.yaml");
  s.end_time_s = 2.4;
  return s;
}
core::Scene seal_scene_elastic_rebounds() {
  core::Scene s = seal_scene();
  s.model.stator_model = core::StatorModel::kElastic;
  s.model.restitution = 0.5;
  s.model.friction_coefficient = 0.4;
  s.end_time_s = 1.8;
  return s;
}

double max_probe_difference_m(const std::vector<core::Sample>& a, const std::vector<core::Sample>& b) {
  double d = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    d = std::max(d, (a[i].probe_displacement_m - b[i].probe_displacement_m).norm());
  }
  return d;
}

TEST(CvodeSwitching, FlexibleRotorSealRubAgreesWithCoreSwitching) {
  for (const core::Scene& s : {seal_scene(), seal_scene_elastic_rebounds()}) {
    const Collect ref = core_reference(s);
    ASSERT_GT(count(ref.events, core::EventKind::kTouchdown), 0);
    const tools::CvodeRun run = expect_agreement(s, ref, true, kFlexibleAgreement_m);
    // Plastic impacts: every event the reference's (a rebound's settling
    // depends on the run's atol: expect_agreement).
    if (s.model.restitution == 0.0) expect_same_event_kinds(run.events_found, ref.events);
    // The probes read the bearing's node (the modal block), not the station.
    const double probes_m = max_probe_difference_m(run.samples, ref.samples);
    std::printf("probes: max difference %.3g m\n", probes_m);
    EXPECT_LT(probes_m, kFlexibleAgreement_m);
    EXPECT_GT((ref.samples.back().probe_displacement_m - ref.samples.back().kin.rotor_pos).norm(), 1e-7);
  }
}

TEST(CvodeSwitching, MotorDriveIsRefusedByName) {
  core::Scene s = paper_scene();
  s.model.drive_model = core::DriveModel::kMotor;
  const tools::CvodeRun run = tools::run_cvode_switching(s, kErrorRate_hz);
  ASSERT_TRUE(run.failure.has_value());
  EXPECT_EQ(*run.failure, "cvode contender: prescribed drive only");
  EXPECT_EQ(run.steps, 0);
  EXPECT_TRUE(run.samples.empty());
}

}  // namespace
