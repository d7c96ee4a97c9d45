#!/usr/bin/env python3
"""rub_monitor: an example monitoring node (a template to copy). Subscribes to
the simulator's state, detects rub from the relative displacement a machine's
probes measure (rub_detector.py), publishes ~alarm (rotor_rub_msgs/RubAlarm)
and /diagnostics, and validates itself against the simulator's contact events
(ground truth, used for nothing else): the detection delay is the time from
the first contact to the first alarm.

The clearance is the simulator's: each state's penetration is |r_r - r_s| - C,
so the monitor takes C from the states it judges (no parameter to keep in
step with the scene).

Topics: it subscribes to the simulator's state and contact_events by their
relative names, so it runs in the simulator's namespace (closed_loop.launch)
or anywhere with a remap. Parameters (private): ~window_s (0.02),
~touch_ratio (0.995), ~raise_fraction (0.5), ~clear_fraction (0.1),
~publish_rate_hz (20: alarm and diagnostics in simulated time, and on every change)."""
import math
import os
import sys

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rotor_rub_msgs.msg import ContactEvent, RotorState, RubAlarm

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from rub_detector import RubDetector, clearance_of  # noqa: E402


class RubMonitor(object):
    def __init__(self):
        if rospy.has_param("~clearance_m"):
            rospy.logwarn("~clearance_m is ignored: the clearance comes from the simulator's states")
        self.settings = (rospy.get_param("~window_s", 0.02), rospy.get_param("~touch_ratio", 0.995),
                         rospy.get_param("~raise_fraction", 0.5), rospy.get_param("~clear_fraction", 0.1))
        self.detector = None  # made on the first state, with the simulator's clearance
        self.period_s = 1.0 / rospy.get_param("~publish_rate_hz", 20.0)
        self.next_publish_s = 0.0
        self.first_contact_s = float("nan")
        self.last_index = None
        self.alarm_pub = rospy.Publisher("~alarm", RubAlarm, queue_size=100, latch=True)
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=10)
        rospy.Subscriber("contact_events", ContactEvent,
                         self.on_event, queue_size=None)
        rospy.Subscriber("state", RotorState, self.on_state,
                         queue_size=None)

    def on_event(self, e):
        if e.kind in (ContactEvent.TOUCHDOWN, ContactEvent.GRAZE) and math.isnan(self.first_contact_s):
            self.first_contact_s = e.time

    def on_state(self, s):
        clearance = clearance_of(s.rotor_position.x, s.rotor_position.y, s.stator_position.x, s.stator_position.y,
                                 s.penetration)
        if self.detector is None:
            rospy.loginfo("clearance %.6g m, from the simulator's states", clearance)
            self.detector = RubDetector(clearance, *self.settings)
        elif self.last_index is not None and s.sample_index <= self.last_index:
            # The simulator was reset (its scene, and so its clearance, may be new).
            self.detector = RubDetector(clearance, *self.settings)
            self.first_contact_s = float("nan")
        self.last_index = s.sample_index
        t = s.header.stamp.to_sec()
        was = self.detector.rubbing
        now = self.detector.feed(t, s.rotor_position.x, s.rotor_position.y, s.stator_position.x,
                                 s.stator_position.y)
        if now != was or t >= self.next_publish_s:
            self.publish(s, t)
            self.next_publish_s = t + self.period_s
            if now and not was:
                first = t == self.detector.first_raised_at
                rospy.loginfo("rub alarm raised at t = %.4f s (orbit %.3f of the clearance, %.0f %% of the window "
                              "touching)%s", t, self.detector.orbit_ratio(), 100 * self.detector.contact_fraction(),
                              "; detection delay %.4f s after the first contact" % (t - self.first_contact_s)
                              if first else "")
            elif was and not now:
                rospy.loginfo("rub alarm cleared at t = %.4f s", t)

    def publish(self, s, t):
        d = self.detector
        a = RubAlarm()
        a.header = s.header
        a.rubbing = d.rubbing
        a.orbit_ratio = d.orbit_ratio()
        a.contact_fraction = d.contact_fraction()
        a.whirl_frequency = d.whirl_frequency_hz()
        a.spin_frequency = s.speed / (2 * math.pi)
        a.raised_at = d.raised_at
        a.detection_delay = d.first_raised_at - self.first_contact_s
        self.alarm_pub.publish(a)
        st = DiagnosticStatus(name="rub_monitor: rub", hardware_id="rotor_rub_sim")
        st.level = DiagnosticStatus.WARN if d.rubbing else DiagnosticStatus.OK
        st.message = ("sustained rub since t = %.4f s" % d.raised_at) if d.rubbing else "no sustained rub"
        st.values = [KeyValue("orbit / clearance", "%.4f" % a.orbit_ratio),
                     KeyValue("window share touching", "%.3f" % a.contact_fraction),
                     KeyValue("whirl frequency [Hz]", "%.2f" % a.whirl_frequency),
                     KeyValue("spin frequency [Hz]", "%.2f" % a.spin_frequency),
                     KeyValue("detection delay [s]", "%.4f" % a.detection_delay)]
        self.diag_pub.publish(DiagnosticArray(header=s.header, status=[st]))


if __name__ == "__main__":
    rospy.init_node("rub_monitor")
    RubMonitor()
    rospy.spin()
