#!/usr/bin/env python3
"""rostest: the node's topics and services (node_topics.test)."""
import math
import os
import subprocess
import sys
import unittest

import rospy
import rostest
from std_srvs.srv import Trigger

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ros_test_support import Collector, PKG, find_binary, run_runner, temp_prefix  # noqa: E402
from rotor_rub_msgs.msg import ContactEvent, RotorState, SolverStats, SpeedCommand, SpeedCommandFeedback  # noqa
from rotor_rub_msgs.msg import Keyphasor, ProbeSignals  # noqa: E402
from rotor_rub_msgs.srv import StepSimulation  # noqa: E402

NODE = "/rotor_rub_sim"
RATE_HZ = 2000.0  # node_topics.test sets output_rate_hz
PROBE_RATE_HZ = 1000.0  # and probe_rate_hz, probe_noise_V 0.01 V
PROBE_ARGS = ["--set", "probe_rate_hz=1000", "--set", "probe_noise_V=0.01"]
END_S = 4.0
# The node and the runner run the same core on the same scene, and the node's
# chunked advance does not change the integrator's steps, so event times are
# the same doubles. The runner's JSON prints them with 17 significant digits,
# which round-trips exactly; 1e-15 s (a few rounding units at t ~ 3 s) only
# absorbs the JSON parse, not any numerical difference.
SAME_CORE_TIME_TOL_S = 1e-15
# Speed is prescribed (kinematic drive): the sample's speed is the profile
# evaluated in double precision.
SPEED_TOL_RAD_PER_S = 1e-9


def expected_speed(t, commands, initial_accel=70.0, initial_target=280.0):
    """The drive's speed for a sequence of (time, target, accel) commands."""
    segs = [(0.0, 0.0, initial_target, initial_accel)]  # (start, speed at start, target, |accel|)
    for (tc, target, accel) in commands:
        v = speed_from(segs, tc)
        segs = [s for s in segs if s[0] < tc] + [(tc, v, target, accel)]
    return speed_from(segs, t)


def speed_from(segs, t):
    seg = [s for s in segs if s[0] <= t][-1]
    t0, v0, target, a = seg
    dv = target - v0
    t_reach = abs(dv) / a
    return target if t - t0 >= t_reach else v0 + math.copysign(a, dv) * (t - t0)


class NodeTestBase(unittest.TestCase):
    WITH_PROBES = False  # the launch file sets probe_rate_hz > 0 (else no "probes" topic)

    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_node_topics")
        cls.states = Collector(NODE + "/state", RotorState)
        cls.events = Collector(NODE + "/contact_events", ContactEvent)
        cls.stats = Collector(NODE + "/solver_stats", SolverStats)
        cls.feedback = Collector(NODE + "/speed_command_feedback", SpeedCommandFeedback)
        cls.keyphasor = Collector(NODE + "/keyphasor", Keyphasor)
        cls.probes = Collector(NODE + "/probes", ProbeSignals)
        for srv in ["reset", "pause", "resume", "step"]:
            rospy.wait_for_service(NODE + "/" + srv, timeout=60)
        cls.reset_srv = rospy.ServiceProxy(NODE + "/reset", Trigger)
        cls.pause_srv = rospy.ServiceProxy(NODE + "/pause", Trigger)
        cls.resume_srv = rospy.ServiceProxy(NODE + "/resume", Trigger)
        cls.step_srv = rospy.ServiceProxy(NODE + "/step", StepSimulation)
        cls.command_pub = rospy.Publisher(NODE + "/speed_command", SpeedCommand, queue_size=100)
        for c in [cls.states, cls.events, cls.stats, cls.feedback, cls.keyphasor] + ([cls.probes] if cls.WITH_PROBES
                                                                                     else []):
            c.wait_connected()
        while cls.command_pub.get_num_connections() == 0:
            rospy.sleep(0.01)

    def fresh_paused_run(self):
        """Reset to t = 0, paused, with every collector empty."""
        if self.stats.msgs and self.stats.msgs[-1].status == SolverStats.RUNNING:
            self.assertTrue(self.pause_srv().success)
        self.assertTrue(self.reset_srv().success)
        # The reset's own statistics (t = 0, paused) mark the start of the run.
        self.stats.wait_for(lambda m: m and m[-1].sim_time == 0.0 and m[-1].status == SolverStats.PAUSED,
                            "the reset's statistics")
        for c in [self.states, self.events, self.stats, self.feedback, self.keyphasor, self.probes]:
            c.clear()

    def run_to_end(self):
        self.assertTrue(self.resume_srv().success)
        n = int(round(END_S * RATE_HZ)) + 1
        states = self.states.wait_for(lambda m: len(m) >= n, "%d states" % n)
        self.stats.wait_for(lambda m: any(s.status == SolverStats.FINISHED for s in m), "the finished statistics")
        return states


class NodeTopicsTest(NodeTestBase):
    """node_topics.test: real_time_factor 0, end_action pause, probes at 1 kHz."""

    WITH_PROBES = True

    def test_1_rate_events_and_runner_agreement(self):
        self.fresh_paused_run()
        states = self.run_to_end()
        n = int(round(END_S * RATE_HZ)) + 1
        self.assertEqual(len(states), n, "one state per output period, none missing, none extra")
        for k, s in enumerate(states):
            self.assertEqual(s.sample_index, k)
            # Stamps are whole nanoseconds: k / rate exactly at 2 kHz.
            self.assertEqual(s.header.stamp.to_nsec(), k * int(1e9 / RATE_HZ))
        prefix = temp_prefix("paper")
        summary = run_runner(["--rate", str(RATE_HZ), "--keyphasor", prefix + ".kp.csv", "--probes",
                              prefix + ".pr.csv"] + PROBE_ARGS, prefix)
        final = [s for s in self.stats.msgs if s.status == SolverStats.FINISHED][-1]
        events = self.events.wait_for(lambda m: len(m) >= len(summary["events"]), "the runner's events")
        self.assertEqual([e.kind_name for e in events], [e["kind"] for e in summary["events"]])
        for got, want in zip(events, summary["events"]):
            self.assertLessEqual(abs(got.time - want["t"]), SAME_CORE_TIME_TOL_S)
        touchdowns = [e.time for e in events if e.kind == ContactEvent.TOUCHDOWN]
        liftoffs = [e.time for e in events if e.kind == ContactEvent.LIFTOFF]
        self.assertAlmostEqual(touchdowns[0], summary["first_touchdown_s"], delta=SAME_CORE_TIME_TOL_S)
        self.assertAlmostEqual(liftoffs[-1], summary["last_liftoff_s"], delta=SAME_CORE_TIME_TOL_S)
        self.assertEqual(final.states_published, n)
        self.assertEqual(final.events_published, len(summary["events"]))
        self.assertEqual(final.steps, summary["stats"]["steps"])
        self.assertGreater(final.real_time_factor, 0.0)
        # The keyphasor and the probes: the runner's marks and signals (the
        # same core, the same seeded noise), to the last digit of its CSV.
        with open(prefix + ".kp.csv") as f:
            marks = [line.split(",") for line in f.read().splitlines()[1:]]
        got = self.keyphasor.wait_for(lambda m: len(m) >= len(marks), "%d keyphasor marks" % len(marks))
        self.assertEqual(len(got), len(marks))
        for k, (msg, row) in enumerate(zip(got, marks)):
            self.assertEqual(msg.revolution, k + 1)
            self.assertEqual(msg.time, float(row[0]))
            self.assertEqual(msg.speed, float(row[2]))
        with open(prefix + ".pr.csv") as f:
            signals = [[float(v) for v in line.split(",")] for line in f.read().splitlines()[1:]]
        self.assertEqual(len(signals), int(END_S * PROBE_RATE_HZ))
        got = self.probes.wait_for(lambda m: len(m) >= len(signals), "%d probe samples" % len(signals))
        for msg, row in zip(got, signals):
            self.assertEqual((msg.time, msg.x, msg.y, msg.x_displacement, msg.y_displacement), tuple(row))

    def send(self, t, target, accel, command_id=0):
        cmd = SpeedCommand()
        cmd.header.stamp = rospy.Time.from_sec(t)
        cmd.target_speed = target
        cmd.acceleration_limit = accel
        cmd.command_id = command_id
        self.command_pub.publish(cmd)

    GOOD = [(0.5, 100.0, 200.0), (1.0, 50.0, 0.0)]  # accel 0: the scene's 70 rad/s^2
    BAD = [(0.7, float("nan"), 10.0), (0.7, -1.0, 10.0), (0.7, 1.0e6, 10.0), (0.7, 100.0, -5.0),
           (0.7, float("inf"), 10.0)]

    def commanded_run(self, with_bad):
        self.fresh_paused_run()
        sent = self.GOOD + (self.BAD if with_bad else [])
        for i, c in enumerate(sent):
            self.send(*c, command_id=100 + i)
        feedback = self.feedback.wait_for(lambda m: len(m) >= len(sent), "feedback on every command")
        res = self.step_srv(2.0)
        self.assertTrue(res.success, res.message)
        self.assertEqual(res.sim_time, 2.0)
        states = self.states.wait_for(lambda m: len(m) >= int(2.0 * RATE_HZ) + 1, "the states up to 2 s")
        return feedback, states

    def test_2_speed_commands(self):
        feedback, states_a = self.commanded_run(with_bad=True)
        accepted = [f for f in feedback if f.accepted]
        rejected = [f for f in feedback if not f.accepted]
        self.assertEqual(len(accepted), len(self.GOOD))
        self.assertEqual(len(rejected), len(self.BAD))
        self.assertEqual(sorted(f.effective_time for f in accepted), [0.5, 1.0])
        self.assertEqual([f.acceleration_limit for f in accepted], [200.0, 70.0])
        # Each answer names the command by the id its sender chose.
        self.assertEqual(sorted(f.command_id for f in feedback), list(range(100, 100 + len(feedback))))
        by_id = {f.command_id: f for f in rejected}
        nan, negative, high, bad_accel, inf = (by_id[100 + len(self.GOOD) + k] for k in range(5))
        self.assertIn("target NaN rad/s is not a finite number; accepted: [0,", nan.reason)
        self.assertIn("is out of range; accepted: [0,", negative.reason)
        self.assertIn("is out of range; accepted: [0,", high.reason)
        # The negative acceleration: its field, and that 0 means the scene's.
        self.assertIn("acceleration_limit -5 rad/s^2 is out of range", bad_accel.reason)
        self.assertIn("or 0 for the scene's acceleration_rad_per_s2 = 70", bad_accel.reason)
        self.assertIn("is not a finite number", inf.reason)
        # The speed follows the commands as specified.
        good = [(t, v, a if a > 0 else 70.0) for (t, v, a) in self.GOOD]
        for s in states_a:
            t = s.header.stamp.to_sec()
            self.assertAlmostEqual(s.speed, expected_speed(t, good), delta=SPEED_TOL_RAD_PER_S, msg="t = %g" % t)
        # The same command sequence again: the identical trajectory.
        _, states_b = self.commanded_run(with_bad=True)
        # Without the rejected commands: still identical (they changed nothing).
        _, states_c = self.commanded_run(with_bad=False)
        for a, b, c in zip(states_a, states_b, states_c):
            self.assertEqual((a.rotor_position, a.stator_position, a.normal_force),
                             (b.rotor_position, b.stator_position, b.normal_force))
            self.assertEqual((a.rotor_position, a.stator_position), (c.rotor_position, c.stator_position))
        self.assertEqual(len(states_a), len(states_b))

    def bad_params(self, name, *params):
        node = find_binary("rotor_rub_sim_node")
        proc = subprocess.run([node, "__name:=" + name] + list(params), capture_output=True, text=True,
                              timeout=60)
        return proc.returncode, proc.stderr + proc.stdout

    def test_4_bad_parameters_end_the_node(self):
        rc, out = self.bad_params("bad_rtol", "_rtol:=-1")
        self.assertEqual(rc, 2)
        self.assertIn("'rtol'", out)
        self.assertIn("accepted: [1e-14, 1]", out)
        rc, out = self.bad_params("bad_typo", "_rtoll:=1e-6")
        self.assertEqual(rc, 2)
        self.assertIn("did you mean 'rtol'", out)
        rc, out = self.bad_params("bad_method", "_method:=euler")
        self.assertEqual(rc, 2)
        self.assertIn("accepted: one of penalty switching iteration", out)
        rc, out = self.bad_params("bad_pace", "_real_time_factor:=-2")
        self.assertEqual(rc, 2)
        self.assertIn("'real_time_factor'", out)
        self.assertIn("accepted: [0, ", out)


class NodeServicesTest(NodeTestBase):
    """node_services.test: real_time_factor 1 and end_action continue, so that
    a pause always lands on a running simulation."""

    def test_3_pause_resume_step_reset(self):
        self.fresh_paused_run()
        res = self.step_srv(0.25)
        self.assertTrue(res.success, res.message)
        self.assertEqual(res.sim_time, 0.25)
        states = self.states.wait_for(lambda m: len(m) >= 501, "the states of a 0.25 s step")
        self.assertEqual(states[-1].header.stamp.to_nsec(), 250000000)
        self.assertFalse(self.step_srv(-1.0).success)  # a bad duration changes nothing
        self.assertFalse(self.step_srv(float("nan")).success)
        # Resume, then pause: the statistics give the time reached.
        self.assertTrue(self.resume_srv().success)
        self.assertFalse(self.step_srv(0.1).success, "step needs a paused simulation")
        res = self.pause_srv()
        self.assertTrue(res.success, res.message)
        # The time reached from the reply ("paused at t = 0.412000 s"): the
        # statistics' last PAUSED may still be the step's, if the resume's
        # RUNNING has not arrived yet.
        t_paused = float(res.message.split("t = ")[1].split()[0])
        k_paused = int(round(t_paused * RATE_HZ))
        states = self.states.wait_for(lambda m: m and m[-1].sample_index == k_paused, "the states up to the pause")
        # While paused nothing advances: the next step's first sample follows on.
        self.assertTrue(self.step_srv(0.01).success)
        states = self.states.wait_for(lambda m: m and m[-1].sample_index == k_paused + 20, "the step after pause")
        seqs = [s.sample_index for s in states]
        self.assertEqual(seqs, list(range(len(seqs))), "no sample skipped or repeated across pause and step")
        # Reset: back to t = 0 at rest.
        self.assertTrue(self.reset_srv().success)
        self.states.clear()
        self.assertTrue(self.step_srv(0.001).success)
        first = self.states.wait_for(lambda m: len(m) >= 3, "the states after reset")[0]
        self.assertEqual(first.sample_index, 0)
        self.assertEqual(first.header.stamp, rospy.Time(0))
        self.assertEqual((first.rotor_position.x, first.rotor_position.y, first.speed), (0.0, 0.0, 0.0))



if __name__ == "__main__":
    if "--services" in sys.argv:
        rostest.rosrun(PKG, "node_services", NodeServicesTest)
    else:
        rostest.rosrun(PKG, "node_topics", NodeTopicsTest)
