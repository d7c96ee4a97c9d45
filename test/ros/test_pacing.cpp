// The node's pace (pacing.hpp), with times passed in: due times at a
// real-time factor, and the achieved factor over running stretches only.
#include <gtest/gtest.h>

#include "rotor_rub_sim/ros/pacing.hpp"

using rotor_rub::ros_node::Pacing;

namespace {
constexpr double kExact = 1e-12;  // sums and quotients of a few doubles
}  // namespace

TEST(Pacing, ASimulatedTimeIsDueAtTheFactorFromTheAnchor) {
  Pacing p;
  p.anchor(100.0, 2.0);
  EXPECT_NEAR(p.due_wall_s(2.5, 0.5), 101.0, kExact);  // 0.5 s simulated at half speed
  EXPECT_NEAR(p.due_wall_s(2.5, 2.0), 100.25, kExact);
  p.anchor(200.0, 3.0);  // a new stretch (after a pause): due from there
  EXPECT_NEAR(p.due_wall_s(3.0, 1.0), 200.0, kExact);
}

// Runs of 2 s simulated in 4 s wall and 1 s in 1 s, a 10 s pause between:
// 3 s in 5 s, however long the pause, and the open stretch counts only
// while running.
TEST(Pacing, TheAchievedFactorExcludesTheTimeBetweenStretches) {
  Pacing p;
  EXPECT_EQ(p.achieved_real_time_factor(0.0, 0.0, true), 0.0);  // nothing run yet
  p.anchor(0.0, 0.0);
  EXPECT_NEAR(p.achieved_real_time_factor(4.0, 2.0, true), 0.5, kExact);
  p.close_stretch(4.0, 2.0);                                // paused
  EXPECT_NEAR(p.running_wall_s(14.0, false), 4.0, kExact);  // the pause is not running time
  EXPECT_NEAR(p.achieved_real_time_factor(14.0, 2.0, false), 0.5, kExact);
  p.anchor(14.0, 2.0);  // resumed
  EXPECT_NEAR(p.running_wall_s(15.0, true), 5.0, kExact);
  EXPECT_NEAR(p.achieved_real_time_factor(15.0, 3.0, true), 0.6, kExact);
  // A lockstep wait: the stretch before it counts, the wait does not.
  p.close_stretch(15.0, 3.0);
  p.anchor(25.0, 3.0);
  EXPECT_NEAR(p.achieved_real_time_factor(26.0, 4.0, true), 4.0 / 6.0, kExact);
  p.clear();  // a reset
  p.anchor(30.0, 0.0);
  EXPECT_NEAR(p.achieved_real_time_factor(32.0, 4.0, true), 2.0, kExact);
}
