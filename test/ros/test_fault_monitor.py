#!/usr/bin/env python3
"""The rub monitor template (rub_monitor.py) against faults injected while the
machine runs (fault_monitor.test). The scene: the paper's rotor at a constant
60 rad/s (0.78 of the critical speed), its damping raised to 10 N s/m so the
start's free whirl has died out (tau = 0.08 s) before the first fault at
0.5 s; its unbalance orbit is then a 0.52 mm circle in the 2 mm clearance.
Faults go in through the inject_fault service while the node waits paused,
so they land at their stamps exactly. Logged per case (docs/benchmarks.md
keeps the blade loss's delay): the fault's time, the first contact after it (ground
truth: contact_events), the monitor's first new channel after it (a channel
raised that was not raised at the fault; the monitor publishes on every
alarm change and at 20 Hz of simulated time besides, so a new channel under
an alarm already raised is seen to 50 ms) and the delays."""
import math
import os
import re
import sys
import unittest

import rosbag
import rospkg
import rospy
import rostest
from rotor_rub_msgs.msg import ContactEvent, Fault, RubAlarm  # noqa: E402
from rotor_rub_msgs.srv import InjectFault

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ros_test_support import Collector, launch_monitored, temp_prefix, wait_last_verdict  # noqa: E402

CONFIG = os.path.join(rospkg.RosPack().get_path("rotor_rub_sim"), "config")
SPEED = 60.0
END_S = 3.0
CHANNELS = ("orbit_at_clearance", "orbit_distorted", "backward_whirl", "drive_braking")
# The blade loss: 5.5e-4 kg m lost opposite the unbalance (phase pi) adds to
# it: e from 0.4 to 1.716 mm, the orbit from 0.52 to 2.23 mm (> C = 2 mm).
BLADE_LOSS = dict(kind=Fault.BLADE_LOSS, magnitude=5.5e-4, phase=math.pi)
# The blade loss's rub holds from its first touch, and orbit_at_clearance
# raises once half of its 20 ms window has the orbit at the clearance
# (measured 9.1 ms after the touch, as on the paper run-up): one window.
BLADE_LOSS_MAX_DELAY_S = 0.020
# Measured: no new channel (see check_change_in_rub).
FRICTION_CHANGE_CHANNEL = ""
SUPPORT_LOOSENING_CHANNEL = ""


def scene():
    with open(os.path.join(CONFIG, "paper_runup.yaml")) as f:
        text = f.read()
    keys = {"initial_speed_rad_per_s": SPEED, "target_speed_rad_per_s": SPEED, "end_time_s": END_S,
            "rotor_damping_N_s_per_m": 10.0}
    for k, v in keys.items():
        text, n = re.subn(r"(?m)^%s:.*$" % k, "%s: %r" % (k, v), text)
        if n == 0:
            text += "\n%s: %r\n" % (k, v)
    path = temp_prefix("fault_scene") + ".yaml"
    with open(path, "w") as f:
        f.write(text)
    return path


def orbit_m(e_m, damping=10.0, m=0.418, k=2493.0):
    """The unbalance response's radius at SPEED (docs/steady_response.md)."""
    return m * e_m * SPEED ** 2 / abs(complex(k - m * SPEED ** 2, damping * SPEED))


class FaultRun(object):
    """closed_loop.launch without the controller, paused at start; the faults
    injected (service), then resumed; the alarms heard and the bag read."""

    def __init__(self, name, faults):
        ns = "fm_" + name
        self.bag = temp_prefix(name) + ".bag"
        alarms = Collector("/%s/rub_monitor/alarm" % ns, RubAlarm)

        def inject_faults():
            inject = rospy.ServiceProxy("/%s/inject_fault" % ns, InjectFault)
            for i, (t_s, fields) in enumerate(faults):
                res = inject(Fault(header=rospy.Header(stamp=rospy.Time.from_sec(t_s)), fault_id=i + 1, **fields))
                assert res.accepted, res.reason

        try:
            out = launch_monitored(["controller:=false", "scene:=" + scene(), "record:=true", "bag:=" + self.bag],
                                   ns, [alarms], inject_faults)
            self.alarms = wait_last_verdict(alarms, END_S, out)
        finally:
            alarms.sub.unregister()
        with rosbag.Bag(self.bag) as b:
            self.events = [m for _, m, _ in b.read_messages(topics=["/%s/contact_events" % ns])]
            self.applied = [m for _, m, _ in b.read_messages(topics=["/%s/parameter_change_feedback" % ns])
                            if m.accepted]

    def first_contact_after(self, t_s):
        touches = [e.time for e in self.events if e.kind != ContactEvent.LIFTOFF and e.time >= t_s]
        return touches[0] if touches else float("nan")

    def channels_at(self, t_s):
        """The channels raised in the last verdict at or before t_s."""
        before = [a for a in self.alarms if a.header.stamp.to_sec() <= t_s]
        return {c for c in CHANNELS if before and getattr(before[-1], c)}

    def first_new_channel_after(self, t_s):
        """(time, channel) of the first verdict after t_s raising a channel
        not raised at t_s; (nan, "") if none."""
        had = self.channels_at(t_s)
        for a in self.alarms:
            t = a.header.stamp.to_sec()
            if t > t_s:
                new = [c for c in CHANNELS if getattr(a, c) and c not in had]
                if new:
                    return t, ",".join(new)
        return float("nan"), ""


def log(case, t_fault, t_contact, t_alarm, channel):
    rospy.loginfo("%s: fault %.4f s, first contact %.4f s (%.4f s after), first new verdict %.4f s (%s): "
                  "%.4f s after the fault, %.4f s after the contact", case, t_fault, t_contact, t_contact - t_fault,
                  t_alarm, channel, t_alarm - t_fault, t_alarm - t_contact)


class FaultMonitorTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_fault_monitor")

    def test_no_fault_no_alarm(self):
        run = FaultRun("none", [])
        self.assertEqual(run.events, [])
        self.assertEqual([a for a in run.alarms if a.rubbing], [])

    def test_blade_loss(self):
        self.assertGreater(orbit_m(0.4e-3 + 5.5e-4 / 0.418), 2e-3)  # the fault's orbit reaches the bore
        run = FaultRun("blade_loss", [(0.5, BLADE_LOSS)])
        t_contact = run.first_contact_after(0.5)
        t_alarm, channel = run.first_new_channel_after(0.5)
        log("blade loss", 0.5, t_contact, t_alarm, channel)
        self.assertEqual([(m.source, m.effective_time) for m in run.applied], [("fault:blade_loss", 0.5)])
        self.assertTrue(math.isfinite(t_contact), "the blade loss started no rub")
        self.assertGreaterEqual(t_alarm, t_contact)
        self.assertLessEqual(t_alarm - t_contact, BLADE_LOSS_MAX_DELAY_S)

    def test_thermal_closure(self):
        # 1.6 mm over 1 s from 0.5 s: the bore reaches the 0.52 mm orbit when
        # C(t) = 2 mm - 1.6 mm (t - 0.5 s) / 1 s falls below it, on the
        # ramp's 1 ms staircase, and stops there (the model's bore is not a
        # moving body: it cannot press into the rotor). The circular orbit
        # then runs along the bore without pressing on it: no force, no
        # torque, an orbit at 0.26 of the design clearance the monitor is
        # configured with. The template raises nothing (measured), and the
        # docs say so; a moving bore would change that.
        r = orbit_m(0.4e-3)
        t_meet = 0.5 + (2e-3 - r) / 1.6e-3
        run = FaultRun("thermal_closure", [(0.5, dict(kind=Fault.THERMAL_CLOSURE, magnitude=1.6e-3, duration=1.0))])
        t_contact = run.first_contact_after(0.5)
        t_alarm, channel = run.first_new_channel_after(0.5)
        log("thermal closure", 0.5, t_contact, t_alarm, channel)
        # One answer for the ramp, its note saying where the closure stopped.
        self.assertEqual([(m.source, m.steps) for m in run.applied], [("fault:thermal_closure", 1000)])
        stopped = re.search(r"stopped at the rotor at t = ([0-9.]+) s", run.applied[0].reason)
        self.assertTrue(stopped, "the closure never met the rotor: " + run.applied[0].reason)
        self.assertAlmostEqual(float(stopped.group(1)), t_meet, delta=1e-3)  # one step of the staircase
        self.assertEqual([a for a in run.alarms if a.rubbing], [])

    # A friction change or a loosened support changes a rub the monitor
    # already reports (orbit_at_clearance, from 9 ms after the blade loss's
    # first contact): the template judges rub, not its severity, and raises
    # no new channel (measured: the drive's torque rise stays near 1e-6 N m,
    # far below drive_braking's threshold). The alarm stands throughout.
    def check_change_in_rub(self, case, fault):
        run = FaultRun(case, [(0.5, BLADE_LOSS), (2.0, fault)])
        self.assertTrue(math.isfinite(run.first_contact_after(0.5)))
        t_alarm, channel = run.first_new_channel_after(2.0)
        log(case + " (in the rub a blade loss at 0.5 s started)", 2.0, run.first_contact_after(2.0), t_alarm, channel)
        before = [a for a in run.alarms if a.header.stamp.to_sec() <= 2.0][-1]
        last = run.alarms[-1]
        self.assertTrue(before.rubbing and last.rubbing, case + ": the alarm did not stand through the change")
        rospy.loginfo("%s: at the fault %s (torque rise %.4g N m, orbit %.3f C); at the end %s (torque rise %.4g N m, "
                      "orbit %.3f C)", case, before.reasons, before.torque_rise, before.orbit_ratio, last.reasons,
                      last.torque_rise, last.orbit_ratio)
        return t_alarm, channel

    def test_friction_change_in_a_rub(self):
        t_alarm, channel = self.check_change_in_rub("friction_change", dict(kind=Fault.FRICTION_CHANGE, magnitude=0.4))
        self.assertEqual(channel, FRICTION_CHANGE_CHANNEL)

    def test_support_loosening_in_a_rub(self):
        t_alarm, channel = self.check_change_in_rub("support_loosening",
                                                    dict(kind=Fault.SUPPORT_LOOSENING, magnitude=0.9))
        self.assertEqual(channel, SUPPORT_LOOSENING_CHANNEL)


if __name__ == "__main__":
    rostest.rosrun("rotor_rub_sim", "fault_monitor", FaultMonitorTest)
