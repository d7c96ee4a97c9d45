// The command schedule (command_schedule.hpp), the node's determinism
// contract without ROS: stamped commands apply exactly at their stamps in
// arrival order, whatever the caller's chunks; past stamps; a fault's steps
// from the scene at its stamp; a closure clamped at the rotor; a ramp
// answered once, and once more when cut.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/command_schedule.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

// The node's loop (SimNode::advance_to): advance to the next command or t_s,
// whichever first, applying what is due on the way.
void advance(core::Simulation& sim, core::CommandSchedule& schedule, double t_s, core::SimulationObserver& out,
             std::vector<core::ChangeAnswer>& answers) {
  schedule.apply_due(sim, answers);
  while (!sim.failure() && sim.time() < t_s) {
    const double before = sim.time();
    if (!sim.advance_to(std::min(t_s, schedule.next_time_s()), out)) break;
    schedule.apply_due(sim, answers);
    if (sim.time() <= before) break;
  }
}

core::Scene short_paper_scene(double end_s) {
  core::Scene s = test::paper_scene();
  s.end_time_s = end_s;
  return s;
}

const core::ChangeAnswer& by_id(const std::vector<core::ChangeAnswer>& answers, std::uint32_t id) {
  const auto it = std::find_if(answers.begin(), answers.end(), [id](const auto& a) { return a.id == id; });
  if (it == answers.end()) throw std::runtime_error("no answer " + std::to_string(id));
  return *it;
}

}  // namespace

// Two changes stamped alike apply at that instant exactly, in the order
// they arrived (the later one's value stays); one stamped later waits.
TEST(CommandSchedule, StampedChangesApplyAtTheirStampsInArrivalOrder) {
  core::Simulation sim(short_paper_scene(0.2));
  core::CommandSchedule schedule(sim.scene().output_rate_hz);
  std::vector<core::ChangeAnswer> answers;
  schedule.change_parameters(sim, 0.15, {{"friction_coefficient", "0.3"}}, 3, "test", answers);
  schedule.change_parameters(sim, 0.05, {{"friction_coefficient", "0.2"}}, 1, "test", answers);
  schedule.change_parameters(sim, 0.05, {{"friction_coefficient", "0.25"}}, 2, "test", answers);
  EXPECT_TRUE(answers.empty());  // all queued
  EXPECT_EQ(schedule.next_time_s(), 0.05);
  test::Collect out;
  advance(sim, schedule, 0.1, out, answers);
  ASSERT_EQ(answers.size(), 2u);
  EXPECT_EQ(answers[0].id, 1u);
  EXPECT_EQ(answers[1].id, 2u);
  for (const auto& a : answers) {
    EXPECT_TRUE(a.accepted) << a.reason;
    EXPECT_EQ(a.start_s, 0.05);
    EXPECT_EQ(a.steps, 1u);
  }
  EXPECT_EQ(answers[0].from.at("friction_coefficient"), 0.1);
  EXPECT_EQ(answers[1].from.at("friction_coefficient"), 0.2);
  EXPECT_EQ(sim.scene().model.friction_coefficient, 0.25);
  advance(sim, schedule, 0.2, out, answers);
  EXPECT_EQ(by_id(answers, 3).start_s, 0.15);
  EXPECT_EQ(sim.scene().model.friction_coefficient, 0.3);
}

// A stamp already simulated: a change is refused (answered, nothing
// changed), a fault is refused to the caller, a speed command applies at
// once; stamp 0 means the next instant reached.
TEST(CommandSchedule, PastStampsAreRefusedButASpeedCommandSteers) {
  core::Simulation sim(short_paper_scene(0.2));
  core::CommandSchedule schedule(sim.scene().output_rate_hz);
  std::vector<core::ChangeAnswer> answers;
  test::Collect out;
  advance(sim, schedule, 0.1, out, answers);
  schedule.change_parameters(sim, 0.05, {{"friction_coefficient", "0.3"}}, 1, "test", answers);
  ASSERT_EQ(answers.size(), 1u);
  EXPECT_FALSE(answers[0].accepted);
  EXPECT_NE(answers[0].reason.find("stamp 0.050000000 s is in the past (simulated time 0.100000000 s)"),
            std::string::npos)
      << answers[0].reason;
  EXPECT_EQ(sim.scene().model.friction_coefficient, 0.1);
  EXPECT_THROW(schedule.inject_fault(sim, 0.05, {core::FaultKind::kFrictionChange, 0.3, 0.0, 0.0}, 2, answers),
               std::invalid_argument);
  const core::SpeedAnswer late = schedule.command_speed(sim, 0.05, 100.0, 0.0);
  EXPECT_TRUE(late.accepted) << late.reason;
  EXPECT_EQ(late.effective_time_s, 0.1);
  EXPECT_EQ(late.accel_rad_per_s2, sim.scene().speed.acceleration_rad_per_s2);  // 0 asks for the scene's
  schedule.change_parameters(sim, 0.0, {{"friction_coefficient", "0.3"}}, 3, "test", answers);
  EXPECT_TRUE(by_id(answers, 3).accepted);
  EXPECT_EQ(by_id(answers, 3).start_s, 0.1);
  const core::SpeedAnswer bad = schedule.command_speed(sim, 0.0, 100.0, -1.0);
  EXPECT_FALSE(bad.accepted);
  EXPECT_NE(bad.reason.find("acceleration_limit -1 rad/s^2 is out of range"), std::string::npos) << bad.reason;
}

// A fault becomes its changes at its stamp, from the scene then in force: a
// blade loss queued while e = 0.4 mm, stamped after a change to 0.6 mm,
// loses its unbalance from 0.6 mm (the vector sum, faults.hpp).
TEST(CommandSchedule, AFaultIsComputedFromTheSceneAtItsStamp) {
  core::Simulation sim(short_paper_scene(0.2));
  core::CommandSchedule schedule(sim.scene().output_rate_hz);
  std::vector<core::ChangeAnswer> answers;
  const double m = sim.scene().model.rotor_mass_kg;
  schedule.change_parameters(sim, 0.05, {{"eccentricity_m", "0.0006"}}, 1, "test", answers);
  schedule.inject_fault(sim, 0.1, {core::FaultKind::kBladeLoss, 0.5 * m * 0.0006, 0.0, 0.0}, 2, answers);
  test::Collect out;
  advance(sim, schedule, 0.2, out, answers);
  const core::ChangeAnswer& loss = by_id(answers, 2);
  EXPECT_TRUE(loss.accepted) << loss.reason;
  EXPECT_EQ(loss.source, "fault:blade_loss");
  EXPECT_EQ(loss.start_s, 0.1);
  EXPECT_NEAR(sim.scene().model.eccentricity_m, 0.0003, 1e-18);
  EXPECT_EQ(loss.from.at("eccentricity_m"), 0.0006);
}

// A fault takes its place among the commands of its instant: a blade loss
// stamped 0.1 s, then a change of the eccentricity stamped 0.1 s too, which
// arrived later, applies after it and stands (the fault's step, computed
// at the stamp, does not overwrite it).
TEST(CommandSchedule, FaultsTakeTheirPlaceAtTheirStamp) {
  core::Simulation sim(short_paper_scene(0.2));
  core::CommandSchedule schedule(sim.scene().output_rate_hz);
  std::vector<core::ChangeAnswer> answers;
  const double m = sim.scene().model.rotor_mass_kg;
  schedule.inject_fault(sim, 0.1, {core::FaultKind::kBladeLoss, 0.5 * m * 0.0004, M_PI, 0.0}, 1, answers);
  schedule.change_parameters(sim, 0.1, {{"eccentricity_m", "0.0002"}}, 2, "test", answers);
  test::Collect out;
  advance(sim, schedule, 0.2, out, answers);
  ASSERT_EQ(answers.size(), 2u);
  EXPECT_EQ(answers[0].id, 1u);
  EXPECT_EQ(answers[1].id, 2u);
  EXPECT_EQ(sim.scene().model.eccentricity_m, 0.0002);
}

// A thermal closure onto the rotor stops where the bore meets it: the
// clearance is held at the rotor-stator distance, and the answer says when.
TEST(CommandSchedule, AClosureStopsAtTheRotor) {
  core::Simulation sim(short_paper_scene(0.2));
  core::CommandSchedule schedule(sim.scene().output_rate_hz);
  std::vector<core::ChangeAnswer> answers;
  test::Collect out;
  advance(sim, schedule, 0.1, out, answers);
  const double distance_m = sim.rotor_stator_distance_m();
  ASSERT_GT(distance_m, 1e-6);
  const double to_1um = sim.scene().model.clearance_m - 1e-6;  // the bore closed to 1 um: onto the rotor
  schedule.inject_fault(sim, 0.0, {core::FaultKind::kThermalClosure, to_1um, 0.0, 0.0}, 1, answers);
  ASSERT_EQ(answers.size(), 1u);
  EXPECT_TRUE(answers[0].accepted) << answers[0].reason;
  EXPECT_EQ(sim.scene().model.clearance_m, std::stod(core::exact_text(distance_m)));
  EXPECT_NE(answers[0].reason.find("the closure stopped at the rotor at t = 0.100000 s"), std::string::npos)
      << answers[0].reason;
}

// A ramp is one answer at its last step, spanning its steps, from the value
// before it to the last; a ramp cut short (the run's end, a reset) is
// answered when cut, with the steps it made; its later steps are dropped.
TEST(CommandSchedule, ARampIsAnsweredOnceSpanningItsSteps) {
  core::Simulation sim(short_paper_scene(0.2));
  const double rate_hz = sim.scene().output_rate_hz, c0 = sim.scene().model.clearance_m;
  core::CommandSchedule schedule(rate_hz);
  std::vector<core::ChangeAnswer> answers;
  const double first_s = schedule.inject_fault(sim, 0.05, {core::FaultKind::kSealWear, 1e-4, 0.0, 0.01}, 1, answers);
  EXPECT_EQ(first_s, 0.05 + 1.0 / rate_hz);
  schedule.inject_fault(sim, 0.15, {core::FaultKind::kSealWear, 1e-4, 0.0, 0.1}, 2, answers);
  test::Collect out;
  advance(sim, schedule, 0.16, out, answers);
  ASSERT_EQ(answers.size(), 1u);
  const core::ChangeAnswer& ramp = answers[0];
  EXPECT_TRUE(ramp.accepted) << ramp.reason;
  EXPECT_EQ(ramp.steps, 10u);
  EXPECT_NEAR(ramp.start_s, 0.051, 1e-15);
  EXPECT_NEAR(ramp.end_s, 0.06, 1e-15);
  EXPECT_EQ(ramp.from.at("clearance_m"), c0);
  EXPECT_NEAR(std::stod(ramp.changes.at("clearance_m")), c0 + 1e-4, 1e-18);
  schedule.close_open_ramps(sim, "the node was reset", answers);
  ASSERT_EQ(answers.size(), 2u);
  const core::ChangeAnswer& cut = answers[1];
  EXPECT_EQ(cut.id, 2u);
  EXPECT_EQ(cut.steps, 10u);  // 0.151 .. 0.160
  EXPECT_NE(cut.reason.find("the ramp was cut at t = 0.160000 s after 10 steps: the node was reset"), std::string::npos)
      << cut.reason;
  EXPECT_TRUE(schedule.empty());  // its later steps dropped
  // One cut before its first step is answered too: refused, nothing made.
  schedule.inject_fault(sim, 0.0, {core::FaultKind::kSealWear, 1e-4, 0.0, 0.1}, 3, answers);
  schedule.close_open_ramps(sim, "the run reached end_time_s", answers);
  ASSERT_EQ(answers.size(), 3u);
  EXPECT_EQ(answers[2].id, 3u);
  EXPECT_FALSE(answers[2].accepted);
  EXPECT_EQ(answers[2].steps, 0u);
  EXPECT_TRUE(schedule.empty());
}

// The contract: the same stamped commands give the same run, sample for
// sample and bit for bit, however the caller chunks its advance (the node's
// pace and its callbacks decide the chunks).
TEST(CommandSchedule, SameStampsSameRunAtAnyChunking) {
  auto run = [](double chunk_s) {
    core::Simulation sim(short_paper_scene(0.3));
    core::CommandSchedule schedule(sim.scene().output_rate_hz);
    std::vector<core::ChangeAnswer> answers;
    schedule.change_parameters(sim, 0.0523, {{"friction_coefficient", "0.3"}, {"clearance_m", "0.0021"}}, 1, "test",
                               answers);
    schedule.command_speed(sim, 0.1017, 120.0, 500.0);
    schedule.inject_fault(sim, 0.1501, {core::FaultKind::kBladeLoss, 2e-4, 1.0, 0.0}, 2, answers);
    schedule.inject_fault(sim, 0.2, {core::FaultKind::kThermalClosure, 1e-4, 0.0, 0.02}, 3, answers);
    test::Collect out;
    for (double t = chunk_s; t < 0.3 + chunk_s; t += chunk_s) advance(sim, schedule, std::min(t, 0.3), out, answers);
    return std::make_pair(out.samples, answers);
  };
  const auto [fine, fine_answers] = run(0.001);
  for (double chunk_s : {0.037, 0.3}) {
    SCOPED_TRACE(chunk_s);
    const auto [coarse, coarse_answers] = run(chunk_s);
    ASSERT_EQ(coarse.size(), fine.size());
    for (std::size_t k = 0; k < fine.size(); ++k) {
      ASSERT_EQ(coarse[k].t_s, fine[k].t_s);
      ASSERT_EQ(coarse[k].kin.rotor_pos, fine[k].kin.rotor_pos) << "t " << fine[k].t_s;
    }
    ASSERT_EQ(coarse_answers.size(), fine_answers.size());
    for (std::size_t k = 0; k < fine_answers.size(); ++k) {
      EXPECT_EQ(coarse_answers[k].start_s, fine_answers[k].start_s);
      EXPECT_EQ(coarse_answers[k].changes, fine_answers[k].changes);
    }
  }
  EXPECT_EQ(fine_answers.size(), 3u);  // the change, the blade loss, the ramp once
}
