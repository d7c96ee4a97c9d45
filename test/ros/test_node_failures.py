#!/usr/bin/env python3
"""The node when its method fails (issue 5), one scene per failure mode: the
exit status of the class, a closed bag holding every state before the failure
(all finite, contiguous) and the failure in the latched SolverStats; with
end_action continue the node stays up, /diagnostics goes to ERROR with the
failure's message, and reset starts the scene again."""
import math
import subprocess
import sys
import unittest

import rosbag
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from rotor_rub_msgs.msg import RotorState, SolverStats
from std_srvs.srv import Trigger

from ros_test_support import Collector, find_binary, temp_prefix

# (name, scene overrides, failure class, exit status)
MODES = [
    ("step_budget", {"max_steps": "300"}, "stalled", 3),
    ("chatter", {"restitution": "1", "max_events_per_ms": "1"}, "stalled", 3),
    ("root_finder", {"method": "iteration", "iteration_max_iterations": "1"}, "not_converged", 5),
    ("wall_budget", {"method": "penalty", "max_wall_time_s": "1e-3"}, "timed_out", 7),
]


def node_args(name, overrides, extra):
    args = [find_binary("rotor_rub_sim_node"), "__name:=" + name, "__ns:=/" + name, "_real_time_factor:=0", "_marker_rate_hz:=0",
            "_publish_clock:=false"]
    return args + ["_%s:=%s" % kv for kv in list(overrides.items()) + list(extra.items())]


class NodeFailures(unittest.TestCase):
    def test_each_mode_exits_with_its_class_and_keeps_the_bag(self):
        for name, overrides, cls, status in MODES:
            with self.subTest(mode=name):
                bag = temp_prefix(name) + ".bag"
                node = "fail_" + name
                p = subprocess.run(node_args(node, overrides, {"record_bag": bag, "end_action": "exit",
                                                              "exit_linger_s": "0"}),
                                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
                self.assertEqual(p.returncode, status, p.stdout[-2000:])
                self.assertIn("failed (%s)" % cls, p.stdout)
                with rosbag.Bag(bag) as b:  # closed and indexed
                    states = [m for _, m, _ in b.read_messages(topics=["/%s/state" % node])]
                    stats = [m for _, m, _ in b.read_messages(topics=["/%s/solver_stats" % node])]
                self.assertTrue(states, "no state recorded before the failure")
                self.assertEqual([s.sample_index for s in states], list(range(len(states))))
                for s in states:
                    for v in (s.rotor_position.x, s.rotor_position.y, s.stator_position.x, s.normal_force, s.speed):
                        self.assertTrue(math.isfinite(v), "non-finite value published at %d" % s.sample_index)
                self.assertEqual(stats[-1].status, SolverStats.FAILED)
                self.assertEqual(stats[-1].failure_class, cls)
                self.assertTrue(stats[-1].failure_message)
                self.assertLessEqual(states[-1].header.stamp.to_sec(), stats[-1].sim_time + 1e-9)

    def test_failed_node_stays_up_reports_error_and_resets(self):
        node = "fail_stay"
        diag = Collector("/diagnostics", DiagnosticArray)
        stats = Collector("/%s/solver_stats" % node, SolverStats)
        states = Collector("/%s/state" % node, RotorState)
        proc = subprocess.Popen(node_args(node, MODES[0][1], {"end_action": "continue"}),
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            def error_status(arrays):
                return [s for a in arrays for s in a.status
                        if s.level == DiagnosticStatus.ERROR and "method failed (stalled)" in s.message]
            diag.wait_for(lambda ms: error_status(ms), "/diagnostics at ERROR")
            self.assertIn("step budget of 300 steps", error_status(diag.msgs)[0].message)
            stats.wait_for(lambda ms: ms and ms[-1].status == SolverStats.FAILED, "SolverStats FAILED")
            self.assertEqual(proc.poll(), None, "the node exited although end_action is continue")
            rospy.wait_for_service("/%s/reset" % node, timeout=60)
            states.clear()
            reset = rospy.ServiceProxy("/%s/reset" % node, Trigger)()
            self.assertTrue(reset.success)
            self.assertIn("paused", reset.message)  # a failed node resets to a paused t = 0
            self.assertTrue(rospy.ServiceProxy("/%s/resume" % node, Trigger)().success)
            # The scene runs again from t = 0 (and fails again the same way).
            got = states.wait_for(lambda ms: any(m.sample_index == 0 for m in ms), "a state from t = 0 after reset")
            self.assertTrue(any(m.sample_index == 0 for m in got))
            stats.wait_for(lambda ms: ms[-1].status == SolverStats.FAILED and ms[-1].sim_time > 0, "FAILED again")
        finally:
            proc.terminate()
            proc.wait(timeout=60)


if __name__ == "__main__":
    rospy.init_node("test_node_failures")
    rostest.rosrun("rotor_rub_sim", "node_failures", NodeFailures, sys.argv)
