#!/usr/bin/env python3
"""rub_monitor: an example machinery-protection node (a template to copy). It
judges rub only from what a machine offers (machine_rub_detector.py, no ROS):
  * the X/Y proximity probes (topic probes, rotor_rub_msgs/ProbeSignals),
  * the keyphasor (topic keyphasor, one mark per revolution with the speed),
  * the drive's speed and torque (topic state: its speed and drive_torque
    fields only; the state's positions, forces, penetration and contact flag
    are never read).
It publishes ~alarm (rotor_rub_msgs/RubAlarm) latched, at publish_rate_hz of
simulated time and on every change, and /diagnostics (WARN while rubbing).
The simulator's contact events serve only as ground truth: the detection
delay is the time from the first contact to the first alarm.

Design data: the clearance and the probes' angles and sensitivity are the
simulator's own scene keys, read from its private parameters
(<ns>/<~simulator>/clearance_m, probe_x_angle_rad, probe_y_angle_rad,
probe_sensitivity_V_per_m, probe_rate_hz); a key the simulator was not
given takes the core's default, as the simulator does (rotor_rub_run
--list-keys prints the key table both use). Never a copy of its own: setting
one of them on the monitor is an error. Probes disabled (probe_rate_hz 0)
end the monitor with status 2 and a line saying so.

Topics: probes, keyphasor, state and contact_events by their relative names,
so it runs in the simulator's namespace (closed_loop.launch) or anywhere with
remaps. It subscribes to state last, after the simulator has accepted its
other subscriptions: a simulator waiting for state subscribers
(wait_for_state_subscribers) then starts only once the monitor hears
everything from t = 0.

Parameters (private): ~simulator (rotor_rub_sim: the simulator node's name,
resolved in the monitor's namespace), ~publish_rate_hz (20), ~wait_timeout_s
(30: wall time to wait for the simulator's topics), and every detector
setting by its name (machine_rub_detector.SETTINGS: ~window_s 0.02,
~touch_ratio 0.995, ~revolutions 4, ~distortion_raise 0.1,
~torque_rise_Nm 0.005, ...). A reset of the simulator (its times start
again) starts a new detector."""
import heapq
import math
import os
import re
import subprocess
import sys
import threading
import time

import roslib.packages
import rospy
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus, KeyValue
from rotor_rub_msgs.msg import ContactEvent, Keyphasor, ProbeSignals, RotorState, RubAlarm

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from machine_rub_detector import (MACHINE_KEYS, SETTINGS, ConfigError, MachineRubDetector,  # noqa: E402
                                  check_settings, machine_config)

STREAMS = ("probes", "keyphasor", "drive", "events")


def key_table_defaults():
    """The core's default of every scene key, from the key table the simulator
    uses (rotor_rub_run --list-keys: 'key  default VALUE  accepted ...')."""
    found = roslib.packages.find_node("rotor_rub_sim", "rotor_rub_run")
    if not found:
        raise ConfigError("cannot find rotor_rub_run (package rotor_rub_sim) for the core's key table")
    out = subprocess.run([found[0], "--list-keys"], check=True, stdout=subprocess.PIPE, text=True).stdout
    return {m.group(1): m.group(2) for m in re.finditer(r"(?m)^(\S+)\s+default (\S+)\s+accepted", out)}


def simulator_design_values():
    """(values, where) of MACHINE_KEYS from the simulator's private parameters,
    the core's defaults for those it was not given."""
    name = rospy.get_param("~simulator", "rotor_rub_sim")
    ns = rospy.resolve_name(name)
    # The simulator's parameters are on the server before it starts (launch
    # files load them first; rosparam load before rosrun). Give a slow start a moment.
    deadline = time.monotonic() + 5.0
    while not rospy.has_param(ns) and time.monotonic() < deadline and not rospy.is_shutdown():
        time.sleep(0.1)
    if not rospy.has_param(ns):
        raise ConfigError("no parameters under %s: is the simulator node %s running in this namespace? (set ~simulator "
                          "to its name)" % (ns, ns))
    defaults = None
    values, where = {}, {}
    for key in MACHINE_KEYS:
        p = ns + "/" + key
        if rospy.has_param(p):
            values[key], where[key] = rospy.get_param(p), "from " + p
        else:
            defaults = defaults if defaults is not None else key_table_defaults()
            if key not in defaults:
                raise ConfigError("%s: not set, and not in the core's key table" % p)
            values[key], where[key] = defaults[key], "the core's default: %s is not set" % p
    return ns, values, where


class RubMonitor(object):
    def __init__(self):
        for key in MACHINE_KEYS:
            if rospy.has_param("~" + key):
                raise ConfigError("~%s is set on the monitor: the design data are the simulator's own parameters "
                                  "(remove it; the monitor reads the simulator's %s)" % (key, key))
        self.sim_ns, values, where = simulator_design_values()
        self.clearance, self.probe_rate, self.geometry = machine_config(values, where)
        self.settings = check_settings({k: rospy.get_param("~" + k) for k in SETTINGS if rospy.has_param("~" + k)},
                                       self.probe_rate)
        rospy.loginfo("rub_monitor: clearance %g m (%s); probes at %g and %g rad, %g V/m, %g Hz (%s)",
                      self.clearance, where["clearance_m"], self.geometry.x_angle_rad, self.geometry.y_angle_rad,
                      self.geometry.sensitivity, self.probe_rate, where["probe_x_angle_rad"])
        self.period_s = 1.0 / rospy.get_param("~publish_rate_hz", 20.0)
        self.lock = threading.RLock()
        self.generation = 0
        self.stream_gen = {s: 0 for s in STREAMS}
        self.stream_last = {s: None for s in STREAMS}
        self.new_run()
        self.alarm_pub = rospy.Publisher("~alarm", RubAlarm, queue_size=10000, latch=True)
        self.diag_pub = rospy.Publisher("/diagnostics", DiagnosticArray, queue_size=10)
        subs = [rospy.Subscriber("contact_events", ContactEvent, self.on_event, queue_size=None),
                rospy.Subscriber("keyphasor", Keyphasor, self.on_keyphasor, queue_size=None),
                rospy.Subscriber("probes", ProbeSignals, self.on_probes, queue_size=None)]
        # Every other topic connected before state: a simulator that waits for
        # its state subscribers then starts with the monitor hearing all of it.
        deadline = time.monotonic() + rospy.get_param("~wait_timeout_s", 30.0)
        while any(s.get_num_connections() == 0 for s in subs) and not rospy.is_shutdown():
            if time.monotonic() > deadline:
                raise ConfigError("no publisher on %s after ~wait_timeout_s: is the simulator running, with probes?"
                                  % ", ".join(s.name for s in subs if s.get_num_connections() == 0))
            time.sleep(0.01)
        rospy.Subscriber("state", RotorState, self.on_state, queue_size=None)

    def new_run(self):
        self.detector = MachineRubDetector(self.clearance, self.geometry, self.settings, self.probe_rate)
        self.first_contact_s = float("nan")
        self.next_publish_s = 0.0
        self.latest_t = 0.0
        self.reached = {"probes": 0.0, "drive": 0.0}
        self.speed = 0.0
        self.was_rubbing = False
        # Readings not yet fed: each stream arrives on its own connection, so
        # the drive can run ahead of the probes (or back); the detector is fed
        # in simulated-time order up to where both have arrived, as replay()
        # feeds it (ties: probes, keyphasor, drive). Fed as they came, a drive
        # reading ahead of the probes could raise drive_braking before the
        # orbit channel saw the same instant (a CI run did).
        self.pending = []
        self.pending_seq = 0

    def accept(self, stream, key):
        """False for a message of a run already replaced. A stream whose key
        goes back (probe time, state sample_index, keyphasor revolution,
        contact event time) has seen the simulator's reset: the first stream to
        see it starts a new detector; the others drop their old run's messages
        still in flight until their own key goes back. (A stream with no
        message in the old run joins the new one at once; a contact event of
        the new run later than the old run's last one cannot be told from an
        old one: rare, and it only affects the ground truth.)"""
        last = self.stream_last[stream]
        if last is not None and key < last:
            if self.stream_gen[stream] == self.generation:
                self.generation += 1
                rospy.loginfo("rub_monitor: the simulator was reset (%s went back): a new run", stream)
                self.new_run()
            self.stream_gen[stream] = self.generation
        elif self.stream_gen[stream] != self.generation:
            if last is not None:
                return False
            self.stream_gen[stream] = self.generation
        self.stream_last[stream] = key
        return True

    def on_event(self, e):
        with self.lock:
            if not self.accept("events", e.time):
                return
            if e.kind in (ContactEvent.TOUCHDOWN, ContactEvent.GRAZE) and math.isnan(self.first_contact_s):
                self.first_contact_s = e.time

    def queue(self, t, order, feed):
        heapq.heappush(self.pending, (t, order, self.pending_seq, feed))
        self.pending_seq += 1

    def on_keyphasor(self, k):
        with self.lock:
            if self.accept("keyphasor", k.revolution):
                d = self.detector
                self.queue(k.time, 1, lambda: d.feed_keyphasor(k.time, k.revolution, k.speed))
                self.after(k.header, None, k.time)

    def on_probes(self, p):
        with self.lock:
            if self.accept("probes", p.time):
                d = self.detector
                self.queue(p.time, 0, lambda: d.feed_probes(p.time, p.x, p.y))
                self.after(p.header, "probes", p.time)

    def on_state(self, s):
        t = s.header.stamp.to_sec()
        with self.lock:
            if self.accept("drive", s.sample_index):
                self.speed = s.speed
                d = self.detector
                self.queue(t, 2, lambda: d.feed_drive(t, s.speed, s.drive_torque))  # the drive's readings only
                self.after(s.header, "drive", t)

    def after(self, header, stream, t):
        d = self.detector
        # Judged up to: the probes and the drive both (each arrives on its own
        # connection; the verdict stamped t covers everything up to t).
        if stream:
            self.reached[stream] = t
        self.latest_t = min(self.reached.values())
        while self.pending and self.pending[0][0] <= self.latest_t:
            heapq.heappop(self.pending)[3]()
        now = d.rubbing
        if now != self.was_rubbing or self.latest_t >= self.next_publish_s:
            self.publish(header)
            self.next_publish_s = self.latest_t + self.period_s
            if now and not self.was_rubbing:
                first = d.first_raised_at == d.raised_at
                rospy.loginfo("rub alarm raised at t = %.4f s (%s; orbit %.3f of the clearance, distortion %.3f)%s",
                              d.raised_at, ",".join(d.reasons()), d.orbit_ratio(),
                              d.last_revolution.distortion if d.last_revolution else float("nan"),
                              "; detection delay %.4f s after the first contact" % (d.raised_at - self.first_contact_s)
                              if first else "")
            elif self.was_rubbing and not now:
                rospy.loginfo("rub alarm cleared at t = %.4f s", d.cleared_at)
            self.was_rubbing = now

    def publish(self, header):
        d = self.detector
        a = RubAlarm()
        a.header.stamp = rospy.Time.from_sec(self.latest_t)
        a.header.frame_id = header.frame_id
        a.rubbing = d.rubbing
        a.orbit_ratio = d.orbit_ratio()
        a.contact_fraction = d.contact_fraction()
        a.spin_frequency = self.speed / (2 * math.pi)
        a.raised_at = d.raised_at
        a.detection_delay = d.first_raised_at - self.first_contact_s
        a.reasons = ",".join(d.reasons())
        a.orbit_at_clearance, a.orbit_distorted, a.backward_whirl, a.drive_braking = (
            d.channels[n].raised for n in ("orbit_at_clearance", "orbit_distorted", "backward_whirl", "drive_braking"))
        r = d.last_revolution
        nan = float("nan")
        if r is not None:
            a.revolution = r.revolution
            a.x_1x_amplitude, a.x_1x_phase, a.y_1x_amplitude, a.y_1x_phase = r.x_1x_m, r.x_1x_lag, r.y_1x_m, r.y_1x_lag
            a.forward_1x, a.backward_1x, a.orbit_distortion = r.forward_1x_m, r.backward_1x_m, r.distortion
            a.backward_share, a.whirl_frequency = r.backward_share, r.whirl_frequency_hz
        else:
            a.forward_1x = a.backward_1x = a.orbit_distortion = a.backward_share = a.whirl_frequency = nan
        a.whirl_direction = d.whirl_direction()
        a.torque_rise, a.speed_dip = d.torque_rise, d.speed_dip
        self.alarm_pub.publish(a)
        st = DiagnosticStatus(name="rub_monitor: rub", hardware_id="rotor_rub_sim")
        st.level = DiagnosticStatus.WARN if d.rubbing else DiagnosticStatus.OK
        st.message = ("rub since t = %.4f s (%s)" % (d.raised_at, a.reasons)) if d.rubbing else "no rub"
        st.values = [KeyValue("orbit / clearance", "%.4f" % a.orbit_ratio),
                     KeyValue("window share at the clearance", "%.3f" % a.contact_fraction),
                     KeyValue("orbit distortion", "%.4f" % a.orbit_distortion),
                     KeyValue("forward 1X [m]", "%.4g" % a.forward_1x),
                     KeyValue("X 1X [m] / lag [deg]", "%.4g / %.1f" % (a.x_1x_amplitude, math.degrees(a.x_1x_phase))),
                     KeyValue("Y 1X [m] / lag [deg]", "%.4g / %.1f" % (a.y_1x_amplitude, math.degrees(a.y_1x_phase))),
                     KeyValue("whirl", {1: "forward", -1: "backward", 0: "unknown"}[a.whirl_direction]),
                     KeyValue("whirl frequency [Hz]", "%.2f" % a.whirl_frequency),
                     KeyValue("spin frequency [Hz]", "%.2f" % a.spin_frequency),
                     KeyValue("torque rise [N m]", "%.4g" % a.torque_rise),
                     KeyValue("speed dip [rad/s]", "%.4g" % a.speed_dip),
                     KeyValue("detection delay [s]", "%.4f" % a.detection_delay)]
        self.diag_pub.publish(DiagnosticArray(header=a.header, status=[st]))


if __name__ == "__main__":
    rospy.init_node("rub_monitor")
    try:
        RubMonitor()
    except (ConfigError, subprocess.CalledProcessError) as e:
        rospy.logfatal("rub_monitor: %s", e)
        sys.exit(2)
    rospy.spin()
