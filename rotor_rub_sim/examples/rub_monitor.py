#!/usr/bin/env python3
"""rub_monitor: an example monitoring node (a template to copy). Subscribes to
the simulator's state, detects rub from the relative displacement a machine's
probes measure (rub_detector.py), publishes ~alarm (rotor_rub_msgs/RubAlarm)
and /diagnostics, and validates itself against the simulator's contact events
(ground truth, used for nothing else): the detection delay is the time from
the first contact to the first alarm.

Parameters (private): ~state_topic (/rotor_rub_sim/state), ~events_topic
(/rotor_rub_sim/contact_events), ~clearance_m (the scene's clearance, default
the rosparam /rotor_rub_sim/clearance_m or 0.002), ~window_s (0.02),
~touch_ratio (0.995), ~raise_fraction (0.5), ~clear_fraction (0.1),
~publish_rate_hz (20: alarm and diagnostics in simulated time, and on every change)."""
import math
import os
import sys

import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rotor_rub_msgs.msg import ContactEvent, RotorState, RubAlarm

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from rub_detector import RubDetector  # noqa: E402


class RubMonitor(object):
    def __init__(self):
        clearance = rospy.get_param("~clearance_m", rospy.get_param("/rotor_rub_sim/clearance_m", 0.002))
        self.detector = RubDetector(clearance, rospy.get_param("~window_s", 0.02),
                                    rospy.get_param("~touch_ratio", 0.995), rospy.get_param("~raise_fraction", 0.5),
                                    rospy.get_param("~clear_fraction", 0.1))
        self.period_s = 1.0 / rospy.get_param("~publish_rate_hz", 20.0)
        self.next_publish_s = 0.0
        self.first_contact_s = float("nan")
        self.last_index = None
        self.alarm_pub = rospy.Publisher("~alarm", RubAlarm, queue_size=100, latch=True)
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=10)
        rospy.Subscriber(rospy.get_param("~events_topic", "/rotor_rub_sim/contact_events"), ContactEvent,
                         self.on_event, queue_size=None)
        rospy.Subscriber(rospy.get_param("~state_topic", "/rotor_rub_sim/state"), RotorState, self.on_state,
                         queue_size=None)

    def on_event(self, e):
        if e.kind in (ContactEvent.TOUCHDOWN, ContactEvent.GRAZE) and math.isnan(self.first_contact_s):
            self.first_contact_s = e.time

    def on_state(self, s):
        if self.last_index is not None and s.sample_index <= self.last_index:
            self.__init_detector_again()  # the simulator was reset
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

    def __init_detector_again(self):
        d = self.detector
        self.detector = RubDetector(d.clearance_m, d.window_s, d.touch_ratio, d.raise_fraction, d.clear_fraction)
        self.first_contact_s = float("nan")

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
