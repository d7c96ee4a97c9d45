#!/usr/bin/env python3
"""runup_controller: an example controller node (a template to copy). It runs
the machine up to its operating speed quickly, to pass the critical speed
before the unbalance response builds up, and backs off when it detects
sustained rub at speed; it acts through the speed command topic only.

Policy (deterministic in the states it has seen):
  * start: target operating_speed_rad_per_s at run_up_accel_rad_per_s2;
  * sustained rub during the run-up (below 90 % of the operating speed): double
    the acceleration, up to max_accel_rad_per_s2, to get through faster;
  * sustained rub (the rub monitor's detector, rub_detector.py, run on the same
    states) at the operating speed (within 10 %): back off to
    (1 - backoff_fraction) x the current speed, and hold there;
  * rub clear for hold_s: resume the run-up to the operating speed.
During the run-up it never backs off: slowing down there would keep the rotor
in the resonance (and in the rub); it accelerates through.

Lockstep (the simulator's lockstep_period_s > 0): the controller answers
every lockstep_state with a command stamped at that state's time, after it
has fed its detector every state up to that one, so the closed loop gives
the same trajectory at any pace. It runs the detector itself rather than
subscribing to the monitor's ~alarm: an alarm from another node would arrive
at a load-dependent time. Without lockstep it commands once per control
period of the states it receives, stamped 0 (applied on receipt).

Topics: state, lockstep_state and speed_command by their relative names (run
it in the simulator's namespace, as closed_loop.launch does, or remap them).
Parameters (private): ~operating_speed_rad_per_s (280), ~run_up_accel_rad_per_s2 (500), ~max_accel_rad_per_s2 (1000),
~backoff_fraction (0.1), ~hold_s (0.2),
~control_period_s (0.01, without lockstep), ~lockstep (false; closed_loop.launch sets it with the
simulator's). One run per start: restart the controller after the simulator's reset."""
import math
import os
import sys
import threading

import rospy
from rotor_rub_msgs.msg import RotorState, SpeedCommand

sys.path.insert(0, os.path.dirname(os.path.realpath(__file__)))
from rub_detector import RubDetector, clearance_of  # noqa: E402


class RunUpPolicy(object):
    """The controller's decisions, without ROS: fed the time, whether the
    detector sees sustained rub, and the speed; returns the target speed.
    `accel` is the acceleration limit to command with it."""

    def __init__(self, operating, accel, max_accel, backoff, hold_s, log=lambda msg: None):
        self.operating = operating
        self.accel = accel
        self.max_accel = max_accel
        self.backoff = backoff
        self.hold_s = hold_s
        self.log = log
        self.target = operating
        self.escalated = False
        self.clear_since = None  # when the rub last cleared while backed off

    def decide(self, t, rubbing, speed):
        if rubbing:
            self.clear_since = None
            if speed >= 0.9 * self.operating and self.target >= speed:
                self.target = (1.0 - self.backoff) * speed
                self.log("sustained rub at %.1f rad/s (t = %.3f s): backing off to %.1f rad/s"
                         % (speed, t, self.target))
            elif speed < 0.9 * self.operating and self.accel < self.max_accel and not self.escalated:
                self.accel = min(2.0 * self.accel, self.max_accel)
                self.escalated = True  # once per alarm
                self.log("sustained rub in the run-up at %.1f rad/s (t = %.3f s): accelerating at %.0f rad/s^2"
                         % (speed, t, self.accel))
            return self.target
        self.escalated = False
        if self.target < self.operating:
            # Backed off and clear: resume once the rub has stayed clear for hold_s.
            if self.clear_since is None:
                self.clear_since = t
            if t - self.clear_since >= self.hold_s:
                self.target = self.operating
                self.clear_since = None
                self.log("rub clear for %.2f s (t = %.3f s): resuming to %.1f rad/s" % (self.hold_s, t, self.target))
        return self.target


class RunUpController(object):
    def __init__(self):
        self.policy = RunUpPolicy(rospy.get_param("~operating_speed_rad_per_s", 280.0),
                                  rospy.get_param("~run_up_accel_rad_per_s2", 500.0),
                                  rospy.get_param("~max_accel_rad_per_s2", 1000.0),
                                  rospy.get_param("~backoff_fraction", 0.1), rospy.get_param("~hold_s", 0.2),
                                  log=rospy.loginfo)
        self.period_s = rospy.get_param("~control_period_s", 0.01)
        # Decided once: commands stamped 0 in a lockstep run would make it
        # depend on timing again.
        self.lockstep = rospy.get_param("~lockstep", False)
        # The clearance is the simulator's, taken from its first state
        # (penetration = |r_r - r_s| - C): never a parameter of its own.
        self.detector = None
        self.states = []  # received, not yet fed to the detector
        self.last_fed = -1
        self.last_speed = 0.0
        self.next_control_s = 0.0
        self.cond = threading.Condition()
        self.pub = rospy.Publisher("speed_command", SpeedCommand, queue_size=1000)
        rospy.Subscriber("state", RotorState, self.on_state, queue_size=None)
        rospy.Subscriber("lockstep_state", RotorState, self.on_lockstep, queue_size=None)

    def feed_until(self, index):
        """Feeds the detector every state up to sample index (in order)."""
        for s in sorted(self.states, key=lambda m: m.sample_index):
            if self.detector is None:
                self.detector = RubDetector(clearance_of(s.rotor_position.x, s.rotor_position.y, s.stator_position.x,
                                                         s.stator_position.y, s.penetration))
            if self.last_fed < s.sample_index <= index:
                self.detector.feed(s.header.stamp.to_sec(), s.rotor_position.x, s.rotor_position.y,
                                   s.stator_position.x, s.stator_position.y)
                self.last_fed = s.sample_index
                self.last_speed = s.speed
        self.states = [s for s in self.states if s.sample_index > index]

    def decide(self, t):
        rubbing = self.detector is not None and self.detector.rubbing
        return self.policy.decide(t, rubbing, self.last_speed)

    def command(self, stamp, target):
        cmd = SpeedCommand(target_speed=target, acceleration_limit=self.policy.accel)
        cmd.header.stamp = stamp
        self.pub.publish(cmd)

    def on_state(self, s):
        with self.cond:
            self.states.append(s)
            self.cond.notify_all()
        if self.lockstep:
            return
        t = s.header.stamp.to_sec()
        with self.cond:
            self.feed_until(s.sample_index)
            if t < self.next_control_s:
                return
            self.next_control_s = t + self.period_s
            target = self.decide(t)
        self.command(rospy.Time(0), target)

    def on_lockstep(self, s):
        if not self.lockstep:
            rospy.logwarn_throttle(5.0, "the simulator runs in lockstep but ~lockstep is false: not answering")
            return
        # rospy drops what is published before a subscriber has connected.
        while self.pub.get_num_connections() == 0 and not rospy.is_shutdown():
            rospy.sleep(0.001)
        with self.cond:
            # Every state up to this one first: the simulator published them
            # before this message, on another connection.
            if not self.cond.wait_for(lambda: any(m.sample_index == s.sample_index for m in self.states)
                                      or self.last_fed >= s.sample_index, timeout=30.0):
                rospy.logerr("lockstep: state %d never arrived", s.sample_index)
                return
            self.feed_until(s.sample_index)
            target = self.decide(s.header.stamp.to_sec())
        self.command(s.header.stamp, target)


if __name__ == "__main__":
    rospy.init_node("runup_controller")
    RunUpController()
    rospy.spin()
