#!/usr/bin/env python3
"""A flood of 10,000 bad speed commands in one second (issue 5): every one is
rejected with feedback, the simulation continues unaffected (its states equal
the headless runner's without commands) and the node keeps its publish rate.
The node runs at real_time_factor 1; the test is synchronised on messages."""
import csv
import math
import subprocess
import sys
import time
import unittest

import rospy
import rostest
from rotor_rub_msgs.msg import RotorState, SolverStats, SpeedCommand, SpeedCommandFeedback

from ros_test_support import Collector, find_binary, run_runner, temp_prefix

NODE = "/flood"
COMMANDS = 10000
FLOOD_S = 1.0
RATE_HZ = 1000.0
# At real_time_factor 1 the node publishes RATE_HZ states per wall second; the
# flood may cost it a little pace, not more than 10 %. The pace is the node's
# own (its solver_stats: states published over its wall time), not when this
# process, which sends the flood, got round to receiving them.
MIN_PACE = 0.9
BAD = [  # (target, acceleration limit) the node must reject; max speed is 2000 rad/s
    (float("nan"), 0.0), (float("inf"), 0.0), (-1.0, 0.0), (2500.0, 0.0), (300.0, -5.0), (300.0, float("nan"))]


class CommandFlood(unittest.TestCase):
    def test_flood_is_absorbed(self):
        states = Collector(NODE + "/state", RotorState)
        feedback = Collector(NODE + "/speed_command_feedback", SpeedCommandFeedback)
        stats = Collector(NODE + "/solver_stats", SolverStats)
        pub = rospy.Publisher(NODE + "/speed_command", SpeedCommand, queue_size=COMMANDS)
        proc = subprocess.Popen(
            [find_binary("rotor_rub_sim_node"), "__name:=flood", "__ns:=/flood", "_real_time_factor:=1", "_end_action:=continue",
             "_output_rate_hz:=%g" % RATE_HZ, "_marker_rate_hz:=0", "_publish_clock:=false", "_stats_rate_hz:=20"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            states.wait_connected()
            feedback.wait_connected()
            while pub.get_num_connections() == 0:
                rospy.sleep(0.01)
            states.wait_for(lambda ms: len(ms) >= 200, "200 states before the flood")
            before = stats.wait_for(lambda ms: len(ms) > 0, "solver stats before the flood")[-1]
            start = time.monotonic()
            for i in range(COMMANDS):
                target, accel = BAD[i % len(BAD)]
                pub.publish(SpeedCommand(target_speed=target, acceleration_limit=accel))
                # Spread over FLOOD_S: 10 commands per wall millisecond.
                ahead = start + FLOOD_S * (i + 1) / COMMANDS - time.monotonic()
                if ahead > 0:
                    time.sleep(ahead)
            end = time.monotonic()
            fbs = feedback.wait_for(lambda ms: len(ms) >= COMMANDS, "%d feedbacks" % COMMANDS)
            # The states published while the flood went on arrive promptly.
            states.wait_for(lambda ms: states.arrival_times[-1] > end, "a state after the flood")
            stats.wait_for(lambda ms: stats.arrival_times[-1] > end, "solver stats after the flood")
            after = next(m for m, t in zip(stats.msgs, stats.arrival_times) if t > end)
        finally:
            proc.terminate()
            proc.wait(timeout=60)
        self.assertEqual(len(fbs), COMMANDS)
        self.assertFalse(any(f.accepted for f in fbs), "a bad command was accepted")
        self.assertTrue(all(f.reason for f in fbs))

        with states.cond:
            msgs = list(states.msgs)
        self.assertGreater(after.wall_time - before.wall_time, FLOOD_S)  # the stats span the flood
        pace = (after.states_published - before.states_published) / (RATE_HZ * (after.wall_time - before.wall_time))
        self.assertGreaterEqual(pace, MIN_PACE, "publish rate fell to %.0f %% during the flood" % (100 * pace))
        indices = [m.sample_index for m in msgs]
        self.assertEqual(indices, list(range(indices[0], indices[0] + len(indices))), "states were dropped")

        # Unaffected: the same states as the headless runner without commands
        # (same core, same scene, same grid: the same doubles).
        end_s = msgs[-1].header.stamp.to_sec() + 0.01
        prefix = temp_prefix("flood_runner")
        run_runner(["--rate", "%g" % RATE_HZ, "--set", "end_time_s=%g" % end_s], prefix)
        with open(prefix + ".csv") as f:
            rows = {i: r for i, r in enumerate(csv.DictReader(f))}
        for m in msgs:
            r = rows[m.sample_index]
            self.assertEqual(m.rotor_position.x, float(r["x_r"]), "sample %d differs" % m.sample_index)
            self.assertEqual(m.rotor_position.y, float(r["y_r"]))
            self.assertEqual(m.speed, float(r["speed"]))
        self.assertTrue(math.isfinite(msgs[-1].rotor_position.x))


if __name__ == "__main__":
    rospy.init_node("test_command_flood")
    rostest.rosrun("rotor_rub_sim", "command_flood", CommandFlood, sys.argv)
