#!/usr/bin/env python3
"""rostest: live parameter changes, faults, dynamic_reconfigure and tf
(live_changes.test)."""
import csv
import math
import os
import subprocess
import sys
import unittest

import rosbag
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from dynamic_reconfigure import DynamicReconfigureCallbackException
from dynamic_reconfigure.client import Client
from std_srvs.srv import Trigger

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ros_test_support import PKG, Collector, find_binary, temp_prefix  # noqa: E402
from rotor_rub_msgs.msg import Fault, ParameterChange, ParameterChangeFeedback  # noqa: E402
from rotor_rub_msgs.srv import InjectFault, StepSimulation  # noqa: E402

END_S = 1.3  # the paper run-up grazes first at 1.113 s
RAMP_S, RAMP_WEAR_M = 0.02, 1e-4  # 20 steps at the output's 1 kHz
TF_RATE_HZ = 50.0
LAUNCH_TIMEOUT_S = 300.0


def stamp(t_s):
    return rospy.Time.from_sec(t_s)


class Run(object):
    """sim.launch in namespace ns, paused at start, recording a bag."""

    def __init__(self, ns, real_time_factor):
        self.ns = ns
        self.bag = temp_prefix(ns) + ".bag"
        params = temp_prefix(ns + "_params") + ".yaml"
        with open(params, "w") as f:
            f.write("end_time_s: %g\ntf_rate_hz: %g\n" % (END_S, TF_RATE_HZ))
        self.proc = subprocess.Popen(
            [find_binary("launch_checked.py"), PKG, "sim.launch", "ns:=" + ns, "record:=true", "bag:=" + self.bag,
             "real_time_factor:=%g" % real_time_factor, "start_paused:=true", "params:=" + params],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.changes = rospy.Publisher("/%s/parameter_change" % ns, ParameterChange, queue_size=100)
        self.faults = rospy.Publisher("/%s/faults" % ns, Fault, queue_size=100)
        rospy.wait_for_service("/%s/resume" % ns, timeout=60.0)
        deadline = rospy.Time.now() + rospy.Duration(60.0)
        while self.changes.get_num_connections() == 0 or self.faults.get_num_connections() == 0:
            if rospy.Time.now() > deadline:
                raise AssertionError("the node never subscribed to parameter_change and faults")
            rospy.sleep(0.01)

    def finish(self):
        # The queued inputs reach the paused node before the resume: the node
        # serves its callbacks every 50 ms while paused.
        rospy.sleep(0.5)
        rospy.ServiceProxy("/%s/resume" % self.ns, Trigger)()
        out, _ = self.proc.communicate(timeout=LAUNCH_TIMEOUT_S)
        if self.proc.returncode != 0:
            raise AssertionError("launch %s failed (%d):\n%s" % (self.ns, self.proc.returncode, out[-3000:]))
        return read_bag(self.bag, self.ns)


def read_bag(path, ns):
    topics = {}
    with rosbag.Bag(path) as bag:
        for topic, msg, t in bag.read_messages():
            topics.setdefault(topic.replace("/" + ns + "/", ""), []).append((t.to_sec(), msg))
    return topics


def states(topics):
    return [(m.header.stamp.to_sec(), (m.rotor_position.x, m.rotor_position.y)) for _, m in topics["state"]]


def send_sequence(run):
    """The changes every recorded run gets: friction and clearance at 1.0 s
    (the opened clearance takes the graze at 1.113 s away), a key that cannot
    change at 0.8 s, a blade loss at 1.2 s, a seal wear ramp from 1.25 s and
    one from 1.29 s that the run's end at 1.3 s cuts."""
    run.changes.publish(ParameterChange(header=rospy.Header(stamp=stamp(1.0)), keys=["friction_coefficient",
                                        "clearance_m"], values=[0.3, 2.5e-3], change_id=1, source="test"))
    run.changes.publish(ParameterChange(header=rospy.Header(stamp=stamp(0.8)), keys=["method"], values=[1.0],
                                        change_id=2, source="test"))
    run.faults.publish(Fault(header=rospy.Header(stamp=stamp(1.2)), kind=Fault.BLADE_LOSS, magnitude=1e-4, phase=1.0,
                             fault_id=3))
    run.faults.publish(Fault(header=rospy.Header(stamp=stamp(1.25)), kind=Fault.SEAL_WEAR, magnitude=RAMP_WEAR_M,
                             duration=RAMP_S, fault_id=4))
    run.faults.publish(Fault(header=rospy.Header(stamp=stamp(1.29)), kind=Fault.SEAL_WEAR, magnitude=RAMP_WEAR_M,
                             duration=0.05, fault_id=5))  # cut by the run's end at 1.3 s


class LiveChangesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_live_changes")
        runs = {}
        cls.diagnostics = Collector("/diagnostics", DiagnosticArray)
        for ns, rtf in (("fast", 0.0), ("paced", 1.0)):
            runs[ns] = Run(ns, rtf)
            send_sequence(runs[ns])
        runs["plain"] = Run("plain", 0.0)
        cls.bags = {ns: run.finish() for ns, run in runs.items()}
        cls.bag_paths = {ns: run.bag for ns, run in runs.items()}
        cls.diagnostics.sub.unregister()

    def test_changes_apply_at_their_stamps_and_not_before(self):
        changed, plain = states(self.bags["fast"]), states(self.bags["plain"])
        self.assertEqual(len(changed), len(plain))
        before = [i for i, (t, _) in enumerate(plain) if t <= 1.0]
        self.assertGreater(len(before), 900)
        for i in before:
            self.assertEqual(changed[i], plain[i], "t %g" % plain[i][0])
        after = max(math.hypot(a[1][0] - b[1][0], a[1][1] - b[1][1]) for a, b in zip(changed, plain) if a[0] > 1.0)
        self.assertGreater(after, 1e-6)  # the graze at 1.113 s, there only without the change
        feedback = [m for _, m in self.bags["fast"]["parameter_change_feedback"]]
        by_id = {m.change_id: m for m in feedback}
        self.assertTrue(by_id[1].accepted)
        self.assertEqual(by_id[1].effective_time, stamp(1.0).to_sec())
        self.assertEqual(sorted(by_id[1].keys), ["clearance_m", "friction_coefficient"])
        self.assertFalse(by_id[2].accepted)
        self.assertIn("'method' cannot change while running", by_id[2].reason)
        # The fault: in the bag as asked, and as the change it made at its stamp.
        self.assertEqual([m.fault_id for _, m in self.bags["fast"]["faults"]], [3, 4, 5])
        self.assertTrue(by_id[3].accepted)
        self.assertEqual(by_id[3].source, "fault:blade_loss")
        self.assertEqual(by_id[3].effective_time, stamp(1.2).to_sec())  # exactly its stamp (rospy truncates to ns)
        self.assertEqual(sorted(by_id[3].keys), ["eccentricity_m", "unbalance_phase_rad"])
        self.assertEqual((by_id[3].steps, by_id[3].end_time), (1, by_id[3].effective_time))
        # The ramp: one answer spanning its 20 steps, from the value before it to the last.
        self.assertEqual([m.change_id for m in feedback].count(4), 1)
        ramp = by_id[4]
        self.assertTrue(ramp.accepted, ramp.reason)
        self.assertEqual(ramp.steps, 20)
        self.assertAlmostEqual(ramp.effective_time, 1.25 + RAMP_S / 20, places=9)
        self.assertAlmostEqual(ramp.end_time, 1.25 + RAMP_S, places=9)
        self.assertEqual(list(ramp.keys), ["clearance_m"])
        self.assertEqual(list(ramp.from_values), [2.5e-3])
        self.assertAlmostEqual(ramp.values[0], 2.5e-3 + RAMP_WEAR_M, places=15)
        # A ramp the run's end cuts: answered at the end with the steps it made.
        cut = by_id[5]
        self.assertTrue(cut.accepted, cut.reason)
        self.assertEqual(cut.steps, 10)
        self.assertAlmostEqual(cut.end_time, END_S, places=9)
        self.assertIn("the ramp was cut at t = 1.300000 s after 10 steps: the run reached end_time_s", cut.reason)
        self.assertAlmostEqual(cut.values[0], 2.6e-3 + 10 * RAMP_WEAR_M / 50, places=15)

    def test_the_same_stamped_changes_give_the_same_run_at_any_pace(self):
        self.assertEqual(states(self.bags["fast"]), states(self.bags["paced"]))
        strip = lambda fb: [(m.change_id, m.accepted, m.effective_time, list(m.keys), list(m.values))
                            for _, m in fb]
        self.assertEqual(strip(self.bags["fast"]["parameter_change_feedback"]),
                         strip(self.bags["paced"]["parameter_change_feedback"]))

    def test_tf_frames_are_stamped_in_simulated_time(self):
        tf = [m for _, m in self.bags["fast"]["/tf"]]
        self.assertGreater(len(tf), int(END_S * TF_RATE_HZ) - 2)
        state_at = dict(states(self.bags["fast"]))
        for msg in tf:
            frames = {t.child_frame_id: t for t in msg.transforms}
            self.assertEqual(sorted(frames), ["fast/rotor", "fast/stator"])  # in the node's namespace
            t_s = frames["fast/rotor"].header.stamp.to_sec()
            self.assertAlmostEqual(t_s * TF_RATE_HZ, round(t_s * TF_RATE_HZ), places=6)
            x, y = state_at[t_s]
            rotor = frames["fast/rotor"].transform.translation
            self.assertEqual((rotor.x, rotor.y), (x, y))

    def test_changes_and_faults_in_the_comparison_and_the_picture(self):
        bag = self.bag_paths["fast"]
        out_csv = temp_prefix("compare") + ".csv"
        subprocess.run([find_binary("rotor_rub_compare"), bag, "--csv", out_csv, "--quiet"], check=True)
        with open(out_csv) as f:
            rows = list(csv.DictReader(f))
        self.assertEqual(len(rows), 1)
        self.assertEqual(rows[0]["live_changes"], "4")  # the refused one changed nothing; a ramp is one
        self.assertEqual(float(rows[0]["first_change_s"]), stamp(1.0).to_sec())
        self.assertIn("clearance_m=0.0025 friction_coefficient=0.3", rows[0]["changes"])
        self.assertIn("blade_loss", rows[0]["changes"])
        self.assertIn("1.251..1.27 seal_wear clearance_m=0.0025..clearance_m=0.0026 (20 steps)", rows[0]["changes"])
        pictures = temp_prefix("pictures")
        out = subprocess.run([find_binary("plot_run.py"), bag, "--out", pictures], check=True, capture_output=True,
                             text=True).stdout
        self.assertIn("and 4 live changes", out)
        # The orbit draws each clearance in force: the scene's 2 mm, 2.5 mm from the first sample after
        # the change stamped 1 s (the sample at 1 s is the state the change met), each ramp's once, where
        # it ended (2.6 mm after its last step at 1.27 s; the cut one's at the last sample, 1.3 s, which
        # met its tenth step).
        self.assertIn("orbit.png draws 4 clearances in force: 2 mm from 0.000 s, 2.5 mm from 1.001 s, "
                      "2.6 mm from 1.271 s, 2.618 mm from 1.300 s", out)
        self.assertTrue(os.path.getsize(os.path.join(pictures, "displacement.png")) > 0)

    def test_a_ramp_is_one_mark_in_plot_run(self):
        # plot_run.py marks each answer: the ramp's one answer is one band, beside a plain change and a
        # one-step fault with their own marks.
        import importlib.util
        import rospkg
        spec = importlib.util.spec_from_file_location(
            "plot_run", os.path.join(rospkg.RosPack().get_path(PKG), "rotor_rub_sim", "tools", "plot_run.py"))
        plot_run = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(plot_run)
        applied = [m for _, m in self.bags["fast"]["parameter_change_feedback"] if m.accepted]
        spans = plot_run.change_spans(applied)
        self.assertEqual([(round(t0, 6), round(t1, 6), label) for t0, t1, label in spans],
                         [(1.0, 1.0, "clearance_m 0.0025, friction_coefficient 0.3"), (1.2, 1.2, "blade_loss"),
                          (1.251, 1.27, "seal_wear (20 steps)"), (1.291, 1.3, "seal_wear (10 steps)")])

    def test_rate_diagnostics_of_state_and_keyphasor(self):
        names = {s.name for a in self.diagnostics.msgs for s in a.status}
        for topic in ("state", "keyphasor"):
            self.assertTrue(any(n.endswith(": %s topic status" % topic) for n in names), (topic, sorted(names)))

    def test_reconfigure_keys_and_ranges_are_the_key_tables(self):
        """rqt_reconfigure's view: the server's description against the key
        table (rotor_rub_run --list-keys), and a change out of range refused."""
        run = Run("reconf", 0.0)
        try:
            client = Client("/reconf/rotor_rub_sim", timeout=30)
            offered = {d["name"]: d for d in client.get_parameter_descriptions()}
            listing = subprocess.run([find_binary("rotor_rub_run"), "--list-keys"], check=True, capture_output=True,
                                     text=True).stdout.splitlines()
            live = {}
            for head, desc in zip(listing[0::2], listing[1::2]):
                if "(live" in desc:
                    key = head.split()[0]
                    live[key] = head.split("accepted", 1)[1].strip()
            # The paper scene: an elastic stator, the switching method, the
            # prescribed drive: k_c, c_c and the drive's keys act on none of it.
            inert = {"contact_stiffness_N_per_m", "contact_damping_N_s_per_m", "drive_torque_limit_N_m",
                     "drive_proportional_gain_N_m_s_per_rad", "drive_integral_gain_N_m_per_rad"}
            self.assertEqual(sorted(offered), sorted(set(live) - inert))
            for key, d in offered.items():
                lo, hi = live[key][1:-1].split(", ")
                self.assertEqual(d["min"], float(lo), key)
                self.assertEqual(d["max"], float(hi), key)
            self.assertEqual(client.update_configuration({"friction_coefficient": 0.25})["friction_coefficient"], 0.25)
            # A refused value fails the call (the caller sees it) and leaves the value in force.
            for refused in ({"friction_coefficient": 5.0}, {"restitution": float("nan")}):
                with self.assertRaises(DynamicReconfigureCallbackException, msg=str(refused)):
                    client.update_configuration(refused)
            now = client.get_configuration(timeout=10)
            self.assertEqual(now["friction_coefficient"], 0.25)
            self.assertEqual(now["restitution"], 0.0)
            # A stamp already simulated, and a negative fault: refused, said why.
            feedback = Collector("/reconf/parameter_change_feedback", ParameterChangeFeedback)
            changes = rospy.Publisher("/reconf/parameter_change", ParameterChange, queue_size=10)
            stepped = rospy.ServiceProxy("/reconf/step", StepSimulation)(duration=0.1)
            self.assertTrue(stepped.success, stepped.message)
            feedback.wait_connected()
            while changes.get_num_connections() == 0:
                rospy.sleep(0.01)
            # A fresh connection may drop its first message (rospy): sent
            # until answered; each copy is refused alike.
            answered = lambda: any(m.change_id == 41 for m in feedback.msgs)
            for _ in range(20):
                changes.publish(ParameterChange(header=rospy.Header(stamp=stamp(0.05)), keys=["friction_coefficient"],
                                                values=[0.3], change_id=41, source="test"))
                deadline = rospy.Time.now() + rospy.Duration(1.0)
                while not answered() and rospy.Time.now() < deadline:
                    rospy.sleep(0.02)
                if answered():
                    break
            late = feedback.wait_for(lambda ms: any(m.change_id == 41 for m in ms), "the past stamp's answer")
            self.assertFalse(late[-1].accepted, (late[-1].effective_time, stepped.sim_time))
            self.assertIn("is in the past", late[-1].reason)
            inject = rospy.ServiceProxy("/reconf/inject_fault", InjectFault)
            res = inject(Fault(header=rospy.Header(stamp=stamp(0.05)), kind=Fault.FRICTION_CHANGE, magnitude=0.3))
            self.assertFalse(res.accepted, res)
            self.assertIn("is in the past", res.reason)
            res = inject(Fault(kind=Fault.BLADE_LOSS, magnitude=-1e-4))
            self.assertFalse(res.accepted, res)
            self.assertIn("magnitude -0.0001 is out of range", res.reason)
            self.assertEqual(client.get_configuration()["friction_coefficient"], 0.25)
        finally:
            rospy.ServiceProxy("/reconf/resume", Trigger)()
            run.proc.communicate(timeout=LAUNCH_TIMEOUT_S)


if __name__ == "__main__":
    rostest.rosrun(PKG, "live_changes", LiveChangesTest)
