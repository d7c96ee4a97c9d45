#!/usr/bin/env python3
"""The shell commands of docs/node.md after the set-up (issue 49): rosservice
call step, dynparam list (naming the server), get and set (an accepted value,
and a refused one that fails the call and leaves the value in force),
rostopic pub of a stamped parameter change, tf2_tools' echo.py between the
node's frames, and a blade loss on a flexible rotor checked on receipt and
applied. Each is run as a subprocess, as typed, and its output checked."""
import math
import os
import subprocess
import unittest

import rospkg

import rospy
import rostest
from rotor_rub_msgs.msg import ParameterChangeFeedback, SpeedCommand, SpeedCommandFeedback

from ros_test_support import Collector

SERVER = "/rotor_rub_sim/rotor_rub_sim"


def shell(*args, timeout=60):
    return subprocess.run(list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout)


class ShellTools(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("shell_tools_test")
        rospy.wait_for_service("/rotor_rub_sim/step", timeout=60)

    def test_a_rosservice_steps_the_paused_node(self):
        p = shell("rosservice", "call", "/rotor_rub_sim/step", "duration: 0.1")
        self.assertEqual(p.returncode, 0, p.stdout)
        self.assertIn("success: True", p.stdout)
        self.assertIn("sim_time: 0.1", p.stdout)

    def test_b_dynparam_lists_gets_sets_and_refuses_loudly(self):
        p = shell("rosrun", "dynamic_reconfigure", "dynparam", "list")
        self.assertEqual(p.returncode, 0, p.stdout)
        self.assertIn(SERVER, p.stdout.split())
        p = shell("rosrun", "dynamic_reconfigure", "dynparam", "get", SERVER)
        self.assertEqual(p.returncode, 0, p.stdout)
        self.assertIn("'friction_coefficient': 0.1", p.stdout)
        p = shell("rosrun", "dynamic_reconfigure", "dynparam", "set", SERVER, "friction_coefficient", "0.3")
        self.assertEqual(p.returncode, 0, p.stdout)
        p = shell("rosrun", "dynamic_reconfigure", "dynparam", "set", SERVER, "friction_coefficient", "5")
        self.assertNotEqual(p.returncode, 0, "a refused value must fail the call: " + p.stdout)
        self.assertIn("responded with an error", p.stdout)
        p = shell("rosrun", "dynamic_reconfigure", "dynparam", "get", SERVER)
        self.assertIn("'friction_coefficient': 0.3", p.stdout)

    def test_c_rostopic_pub_of_a_stamped_change_is_applied(self):
        feedback = Collector("/rotor_rub_sim/parameter_change_feedback", ParameterChangeFeedback)
        feedback.wait_connected()
        # rostopic pub -1 holds the connection 3 s: the stamp (simulated
        # time) must lie ahead of the paused node's time when it arrives.
        p = shell("rostopic", "pub", "-1", "/rotor_rub_sim/parameter_change", "rotor_rub_msgs/ParameterChange",
                  "{header: {stamp: {secs: 1}}, change_id: 7, keys: [clearance_m], values: [0.0021]}")
        self.assertEqual(p.returncode, 0, p.stdout)
        shell("rosservice", "call", "/rotor_rub_sim/step", "duration: 1.0")
        msgs = feedback.wait_for(lambda ms: any(m.change_id == 7 for m in ms), "the change's feedback")
        got = [m for m in msgs if m.change_id == 7][0]
        self.assertTrue(got.accepted, got.reason)
        self.assertEqual(got.effective_time, 1.0)

    def test_d_tf2_echo_prints_the_rotor_in_the_stator(self):
        # /tf is not latched: the node runs while echo.py listens.
        p = shell("rosservice", "call", "/rotor_rub_sim/resume")
        self.assertIn("success: True", p.stdout)
        p = shell("timeout", "8", "rosrun", "tf2_tools", "echo.py", "rotor_rub_sim/stator", "rotor_rub_sim/rotor")
        self.assertIn("- Translation:", p.stdout)
        self.assertIn("in RPY (degree)", p.stdout)


    def test_e_a_blade_loss_on_a_flexible_rotor_is_checked_on_receipt(self):
        # A second node on the seal-rub rotor, started as docs/node.md shows
        # (rosparam load, then rosrun): a blade is lost from a disk, so the
        # message's default node 0 (a bearing) is refused to the caller,
        # naming the disks' nodes; at disk 3 it is accepted and applied at
        # its stamp to the file's unbalances.
        seal = os.path.join(rospkg.RosPack().get_path("rotor_rub_sim"), "config", "seal_rub_runup.yaml")
        p = shell("rosparam", "load", seal, "/flex/rotor_rub_sim")
        self.assertEqual(p.returncode, 0, p.stdout)
        node = subprocess.Popen(["rosrun", "rotor_rub_sim", "rotor_rub_sim_node", "__ns:=/flex", "_start_paused:=true",
                                 "_end_action:=continue"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            rospy.wait_for_service("/flex/inject_fault", timeout=60)
            p = shell("rosservice", "call", "/flex/inject_fault",
                      "{fault: {header: {stamp: {secs: 1}}, fault_id: 3, kind: 0, magnitude: 1.0e-4, phase: 0.0}}")
            self.assertEqual(p.returncode, 0, p.stdout)
            self.assertIn("accepted: False", p.stdout)
            self.assertIn("fault node 0 is out of range", p.stdout)
            self.assertIn("a node with a disk (3, 6, 9)", p.stdout)
            feedback = Collector("/flex/parameter_change_feedback", ParameterChangeFeedback)
            feedback.wait_connected()
            p = shell("rosservice", "call", "/flex/inject_fault",
                      "{fault: {header: {stamp: {secs: 0, nsecs: 10000000}}, fault_id: 4, kind: 0, magnitude: 1.0e-4, "
                      "phase: 0.0, node: 3}}")
            self.assertIn("accepted: True", p.stdout)
            p = shell("rosservice", "call", "/flex/step", "{duration: 0.02}")
            self.assertEqual(p.returncode, 0, p.stdout)
            msgs = feedback.wait_for(lambda ms: any(m.change_id == 4 for m in ms), "the blade loss's feedback")
            got = [m for m in msgs if m.change_id == 4][0]
            self.assertTrue(got.accepted, got.reason)
            self.assertAlmostEqual(got.effective_time, 0.01, places=9)
            applied = dict(zip(got.keys, got.values))
            self.assertEqual(applied["added_unbalance_node"], 3)
            self.assertEqual(applied["added_unbalance_me_kg_m"], 1.0e-4)
            self.assertAlmostEqual(abs(applied["added_unbalance_phase_rad"]), math.pi, places=12)
        finally:
            node.terminate()
            node.wait(timeout=30)


    def test_f_a_constant_speed_node_refuses_a_command_without_an_acceleration(self):
        # acceleration_rad_per_s2 0 holds the speed; a command's acceleration_limit 0
        # means the scene's, which would never reach its target: refused, said why.
        node = subprocess.Popen(["rosrun", "rotor_rub_sim", "rotor_rub_sim_node", "__ns:=/steady", "_start_paused:=true",
                                 "_end_action:=continue", "_initial_speed_rad_per_s:=100.0",
                                 "_target_speed_rad_per_s:=100.0", "_acceleration_rad_per_s2:=0.0"],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            rospy.wait_for_service("/steady/step", timeout=60)
            feedback = Collector("/steady/speed_command_feedback", SpeedCommandFeedback)
            feedback.wait_connected()
            commands = rospy.Publisher("/steady/speed_command", SpeedCommand, queue_size=10)
            while commands.get_num_connections() == 0:
                rospy.sleep(0.01)
            commands.publish(SpeedCommand(target_speed=150.0, acceleration_limit=0.0, command_id=11))
            msgs = feedback.wait_for(lambda ms: any(m.command_id == 11 for m in ms), "the command's feedback")
            got = [m for m in msgs if m.command_id == 11][0]
            self.assertFalse(got.accepted)
            self.assertIn("acceleration_rad_per_s2, which is 0", got.reason)
        finally:
            node.terminate()
            node.wait(timeout=30)


if __name__ == "__main__":
    rostest.rosrun("rotor_rub_sim", "shell_tools", ShellTools)
