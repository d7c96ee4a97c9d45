#!/usr/bin/env python3
"""rostest: bags recorded through the launch files (recording.test)."""
import csv
import math
import os
import subprocess
import sys
import time
import unittest

import rosbag
import rospkg
import rospy
import rostest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ros_test_support import Collector, PKG, WAIT_TIMEOUT_S, find_binary, run_runner, temp_prefix  # noqa: E402
from rotor_rub_msgs.msg import RotorState, SolverStats  # noqa: E402

RATE_HZ = 1000.0  # config/paper_runup.yaml
END_S = 4.0
N_STATES = int(END_S * RATE_HZ) + 1
LAUNCH_TIMEOUT_S = 300.0  # wall bound on one launch (it takes seconds)
# Accuracy of each method against switching at rtol 1e-7, at the tolerances
# compare_methods.launch gives them (measured: iteration 2.1e-6 m, penalty
# 1.8e-6 m on dopri5, docs/benchmarks.md); the bound is the measured figure
# rounded up to the next half decade, so a regression of the method fails.
# The seal-rub example (config/seal_rub_runup.yaml, config/rotors/seal_rub.yaml).
SEAL_SCENE = os.path.join(rospkg.RosPack().get_path(PKG), "config", "seal_rub_runup.yaml")
SEAL_END_S = 3.0
SEAL_RATE_HZ = 1000.0
SEAL_NODE_Z_M = [0.1 * i for i in range(13)]  # 12 elements of 0.1 m
SEAL_STATION_NODE = 6
SHAFT_RATE_HZ = 50.0  # the node's default shaft_rate_hz


METHOD_MAX_ROTOR_DIFF_M = {"iteration": 5e-6, "penalty": 5e-6, "switching": 0.0}


def launch(launch_file, *args):
    """Through launch_checked.py: a node's failure fails the launch (roslaunch
    alone exits 0)."""
    proc = run_launch(launch_file, *args)
    if proc.returncode != 0:
        raise AssertionError("roslaunch %s failed (%d):\n%s" % (launch_file, proc.returncode, proc.stdout[-3000:]))
    return proc


def run_launch(launch_file, *args):
    return subprocess.run([find_binary("launch_checked.py"), PKG, launch_file] + list(args), capture_output=True,
                          text=True, timeout=LAUNCH_TIMEOUT_S)


def compare(*args):
    out_csv = temp_prefix("figures") + ".csv"
    subprocess.run([find_binary("rotor_rub_compare")] + list(args) + ["--csv", out_csv, "--quiet"], check=True)
    with open(out_csv) as f:
        return {row["run"]: row for row in csv.DictReader(f)}


class RecordingTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("test_recording")
        cls.runner_prefix = temp_prefix("runner")
        cls.runner = run_runner([], cls.runner_prefix)
        cls.sim_bag = temp_prefix("sim") + ".bag"
        launch("sim.launch", "record:=true", "bag:=" + cls.sim_bag, "real_time_factor:=0")

    def test_a_failed_node_fails_the_launch_at_once(self):
        # roslaunch exits 0 when a node fails; launch_checked.py exits with
        # the node's status and ends the launch at once (compare_methods used
        # to wait 60 s for nodes that had died).
        typo = temp_prefix("typo") + ".yaml"
        with open(typo, "w") as f:
            f.write("clearence_m: 0.002\n")
        for launch_file in ("sim.launch", "compare_methods.launch"):
            start = time.time()
            proc = run_launch(launch_file, "params:=" + typo, "real_time_factor:=0")
            self.assertEqual(proc.returncode, 2, launch_file + ": " + proc.stdout[-2000:] + proc.stderr[-500:])
            self.assertIn("exited with status 2", proc.stderr)
            self.assertLess(time.time() - start, 60.0, launch_file)  # at once: ~2 s; never the 60 s of a hang
        # A normal end is not reported as a crash.
        proc = launch("sim.launch", "real_time_factor:=0")
        self.assertNotIn("REQUIRED process", proc.stdout)

    def test_leftover_parameter_does_not_poison_a_later_launch(self):
        # A typo left on the master by an earlier run (issue 15): the launch
        # files clear the node's parameters at start, so the run goes on.
        rospy.set_param("/rotor_rub_sim/rotor_rub_sim/clearence_m", 0.002)
        bag = temp_prefix("leftover") + ".bag"
        launch("sim.launch", "record:=true", "bag:=" + bag, "real_time_factor:=0")
        with rosbag.Bag(bag) as b:
            self.assertEqual(b.get_message_count(topic_filters=["/rotor_rub_sim/state"]), N_STATES)
        self.assertFalse(rospy.has_param("/rotor_rub_sim/rotor_rub_sim/clearence_m"))

    def test_sim_launch_bag_holds_every_message(self):
        with rosbag.Bag(self.sim_bag) as bag:
            counts = {t: i.message_count for t, i in bag.get_type_and_topic_info().topics.items()}
            states = [m for _, m, _ in bag.read_messages(topics=["/rotor_rub_sim/state"])]
            seqs = [m.sample_index for m in states]
            stats = [m for _, m, _ in bag.read_messages(topics=["/rotor_rub_sim/solver_stats"])]
        self.assertEqual(counts["/rotor_rub_sim/state"], N_STATES)
        self.assertEqual(sorted(seqs), list(range(N_STATES)), "every sample index once: none lost")
        # header.seq as on the live topic (roscpp numbers each publisher's
        # messages 0, 1, ...: here the sample index), not 0.
        self.assertEqual([m.header.seq for m in states], seqs)
        self.assertEqual(counts["/clock"], N_STATES - 1)  # t = 0 has no clock
        self.assertEqual(counts["/rotor_rub_sim/contact_events"], len(self.runner["events"]))
        self.assertEqual(counts["/rotor_rub_sim/markers"], int(END_S * 30) + 1)  # marker_rate_hz 30
        # /diagnostics too (issue 15: it was promised and left out), at its
        # rate of 2 Hz of simulated time plus the start and the end.
        self.assertGreaterEqual(counts["/diagnostics"], int(END_S * 2))
        with rosbag.Bag(self.sim_bag) as bag:
            names = {st.name for _, m, _ in bag.read_messages(topics=["/diagnostics"]) for st in m.status}
        self.assertIn("rotor_rub_sim/rotor_rub_sim: solver", names)  # the node's full name: ns/name
        # ... every status the live topic carries, the topics' rates among them.
        self.assertEqual(sorted(n.split(": ", 1)[1] for n in names),
                         ["contact", "keyphasor topic status", "real-time factor", "solver", "state topic status"])
        self.assertEqual(stats[-1].status, SolverStats.FINISHED)
        self.assertEqual(stats[-1].states_published, N_STATES)
        self.assertNotIn("/rotor_rub_sim/shaft", counts, "the Jeffcott has no shaft topic")

    def test_flexible_rotor_shaft_in_the_bag(self):
        # The seal-rub example through sim.launch (its rotor_file found in the
        # package's config/): the deflected shaft at shaft_rate_hz (50) in
        # simulated time, every node along the file's shaft, the rub station's
        # node where the state puts the rotor, and its markers.
        bag_path = temp_prefix("shaft") + ".bag"
        launch("sim.launch", "params:=" + SEAL_SCENE, "record:=true", "bag:=" + bag_path, "real_time_factor:=0")
        with rosbag.Bag(bag_path) as bag:
            shafts = [m for _, m, _ in bag.read_messages(topics=["/rotor_rub_sim/shaft"])]
            states = {m.sample_index: m for _, m, _ in bag.read_messages(topics=["/rotor_rub_sim/state"])}
            markers = [mk for _, m, _ in bag.read_messages(topics=["/rotor_rub_sim/markers"]) for mk in m.markers
                       if mk.ns == "shaft"]
        self.assertEqual(len(shafts), int(SEAL_END_S * SHAFT_RATE_HZ))  # k / 50 s, k = 1 .. 150
        self.assertEqual([m.time for m in shafts], [k / SHAFT_RATE_HZ for k in range(1, len(shafts) + 1)])
        touched = 0.0
        for m in shafts:
            self.assertEqual(len(m.nodes), len(SEAL_NODE_Z_M))
            for p, z in zip(m.nodes, SEAL_NODE_Z_M):
                self.assertAlmostEqual(p.z, z, delta=1e-12)  # lengths summed element by element
            self.assertEqual(m.station_node, SEAL_STATION_NODE)
            state = states[int(round(m.time * SEAL_RATE_HZ))]
            station = m.nodes[m.station_node]
            # The same dense output at the same instant (k / 50 against
            # 20 k / 1000: equal to the last bits of t), and the station's row
            # of the expansion is the identity on u: rounding only.
            self.assertAlmostEqual(station.x, state.rotor_position.x, delta=1e-15)
            self.assertAlmostEqual(station.y, state.rotor_position.y, delta=1e-15)
            touched = max(touched, max(math.hypot(p.x, p.y) for p in m.nodes))
        # The run goes through its critical speed: the shaft bends by micrometres.
        self.assertGreater(touched, 1e-6)
        self.assertLess(touched, 1e-3)
        self.assertEqual(len(markers), 2 * len(shafts))  # the centreline and the node spheres
        for mk in markers:
            self.assertEqual(len(mk.points), len(SEAL_NODE_Z_M))

    def test_compare_tool_reproduces_the_runner(self):
        rows = compare(self.sim_bag, "--runner", self.runner_prefix)
        run = [r for name, r in rows.items() if name.endswith(":/rotor_rub_sim")][0]
        self.assertEqual(int(run["lost_samples"]), 0)
        self.assertEqual(int(run["common_samples"]), N_STATES)
        # The same core on the same scene: identical samples and events.
        for column in ["max_rotor_diff_m", "max_stator_diff_m", "max_normal_force_diff_N", "first_contact_diff_s",
                       "last_contact_end_diff_s"]:
            self.assertEqual(float(run[column]), 0.0, column)
        self.assertAlmostEqual(float(run["first_contact_s"]), self.runner["first_contact_s"], delta=1e-9)
        self.assertAlmostEqual(float(run["max_orbit_m"]), self.runner["max_orbit_m"], delta=1e-12)
        self.assertEqual(int(run["steps"]), self.runner["stats"]["steps"])
        # The integrator that ran, from the bag's SolverStats and the runner's summary alike: on the
        # paper scene (switching, rtol 1e-6) `auto` resolved to dop853, as the README states.
        self.assertEqual(self.runner["integrator"], "dop853")
        for name, r in rows.items():
            self.assertEqual(r["integrator"], self.runner["integrator"], name)

    def test_compare_methods_launch_records_three_runs(self):
        bag = temp_prefix("compare") + ".bag"
        launch("compare_methods.launch", "record:=true", "bag:=" + bag)
        rows = compare(bag, "--reference", "/switching")
        self.assertEqual(len(rows), 3)
        for name, row in rows.items():
            method = row["method"]
            self.assertTrue(name.endswith(":/%s" % method), name)  # the run's namespace
            self.assertEqual(int(row["samples"]), N_STATES, name)
            self.assertEqual(int(row["lost_samples"]), 0, name)
            self.assertLessEqual(float(row["max_rotor_diff_m"]), METHOD_MAX_ROTOR_DIFF_M[method], name)
        self.assertFalse([p for p in os.listdir(os.path.dirname(bag)) if p.endswith(".part")], "parts merged")

    def test_rosbag_play_drives_a_subscriber(self):
        states = Collector("/rotor_rub_sim/state", RotorState)
        # Played at 8x the recorded (simulated) pace; --wait-for-subscribers
        # holds the playback until our subscriber is connected; a queue for
        # every state, so a subscriber held up by a loaded machine loses none.
        subprocess.run(["rosbag", "play", "-q", "-r", "8", "--queue", "100000", "--wait-for-subscribers", self.sim_bag,
                        "--topics", "/rotor_rub_sim/state"], check=True, timeout=WAIT_TIMEOUT_S)
        got = states.wait_for(lambda m: len(m) >= N_STATES, "the played states")
        self.assertEqual([m.sample_index for m in got], list(range(N_STATES)))


if __name__ == "__main__":
    rostest.rosrun(PKG, "recording", RecordingTest)
