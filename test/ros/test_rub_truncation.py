#!/usr/bin/env python3
"""rub_truncation.py (the contact's quantities against the modes kept): its
recommendation on the seal-rub example cut to 1.5 s (a tolerance and a choice
of quantities that admit a model, the defaults that admit none, naming the
peak force), the reference (the full FE model: 26 planar modes on the seal
rotor, 2 on a rotor of one node), the judging logic on made-up rows (a model that agrees
by chance below one that does not is not recommended; first contact in
revolutions), bad arguments and a failed run."""
import csv
import importlib.util
import os
import subprocess
import sys
import unittest

import rospkg
import rostest

from ros_test_support import PKG, find_binary, temp_prefix

ROOT = rospkg.RosPack().get_path(PKG)
SEAL = os.path.join(ROOT, "config", "seal_rub_runup.yaml")
PAPER = os.path.join(ROOT, "config", "paper_runup.yaml")
JEFFCOTT_ROTOR = os.path.join(ROOT, "test", "data", "rotors", "jeffcott_matrices.yaml")
CUT = ["--set", "end_time_s=1.5"]  # the first contact is at 1.242 s


def tool(*args):
    return subprocess.run([find_binary("rub_truncation.py"), find_binary("rotor_rub_run")] + list(args),
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=300)


def load_module():
    path = os.path.join(ROOT, "rotor_rub_sim", "tools", "rub_truncation.py")
    spec = importlib.util.spec_from_file_location("rub_truncation", path)
    m = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(m)
    return m


class Recommendation(unittest.TestCase):
    def test_a_tolerance_that_admits_a_model(self):
        # Without the peak force, 8 planar modes are within 5 %; 4 are not (the probe's orbit 5.2 % off).
        out = temp_prefix("admits") + ".csv"
        r = tool("--scene", SEAL, *CUT, "--modes", "2", "4", "8", "--quantities", "first_contact", "orbit_station",
                 "orbit_probe", "--csv", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("recommended: 8 planar modes (16 coordinates)", r.stdout)
        self.assertIn("not judged: max_force", r.stdout)
        self.assertIn("reference: the full FE model (26 planar modes, 52 DOF: every mode kept)", r.stdout)
        with open(out) as f:
            rows = list(csv.DictReader(f))
        self.assertEqual([row["planar_modes"] for row in rows], ["2", "4", "8", "26"])
        self.assertEqual([row["within"] for row in rows], ["0", "0", "1", "1"])
        ref = rows[-1]
        self.assertEqual(ref["reference"], "1")
        for k in ("first_contact_err_s", "max_normal_force_err_rel", "max_orbit_station_err_rel",
                  "max_orbit_probe_err_rel"):
            self.assertEqual(float(ref[k]), 0.0, k)
        self.assertAlmostEqual(float(ref["first_contact_s"]), 1.2424, delta=1e-3)
        self.assertGreater(float(rows[1]["max_orbit_probe_err_rel"]), 0.05)
        self.assertLess(float(rows[2]["max_orbit_probe_err_rel"]), 0.05)
        self.assertGreater(float(rows[2]["max_orbit_probe_m"]), 1e-6)  # the bearing moves: the probe was read

    def test_the_defaults_admit_none_and_name_the_peak_force(self):
        r = tool("--scene", SEAL, *CUT, "--modes", "4", "8")
        self.assertEqual(r.returncode, 1, r.stderr)
        last = r.stdout.strip().splitlines()[-1]
        self.assertTrue(last.startswith("recommended: none: max_force does not converge within 0.05 (at 8 planar "
                                        "modes"), last)
        self.assertTrue(last.endswith("only the full FE model, the reference, is within"), last)

    def test_the_full_fe_model_is_the_reference_when_every_mode_fits(self):
        # A one-node rotor (4 DOF, 2 planar modes): the Jeffcott for any number of modes.
        r = tool("--scene", PAPER, "--set", "rotor_file=" + JEFFCOTT_ROTOR, *CUT, "--modes", "1", "--tolerance", "1e-4")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("reference: the full FE model (2 planar modes, 4 DOF: every mode kept)", r.stdout)
        self.assertIn("recommended: 1 planar mode (2 coordinates)", r.stdout)
        r = tool("--scene", PAPER, "--set", "rotor_file=" + JEFFCOTT_ROTOR, "--modes", "2")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--modes: value 2 is not below the reference (2 planar modes); accepted: integers in [1, 1]",
                      r.stderr)

    def test_a_method_the_runner_does_not_offer_is_refused_naming_those_it_does(self):
        r = tool("--scene", SEAL, "--method", "spring")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--method: value 'spring' is not accepted; accepted: one of penalty switching iteration", r.stderr)


class Logic(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.m = load_module()

    def row(self, modes, t, force, orbit, probe, speed=2 * 3.141592653589793):
        return {"modes": modes, "first_contact_s": t, "speed_at_first_contact": speed, "max_force": force,
                "orbit_station": orbit, "orbit_probe": probe}

    def test_judge_and_recommend(self):
        m = self.m
        ref = self.row(20, 1.0, 10.0, 2e-5, 1e-6)  # 1 rev/s at the first contact: 0.05 rev = 0.05 s
        rows = [self.row(1, 1.0, 10.1, 2e-5, 1e-6),    # within (by chance)
                self.row(2, 1.06, 10.0, 2e-5, 1e-6),   # first contact 0.06 rev late: beyond
                self.row(4, 0.96, 10.4, 2e-5, 1e-6),   # 0.04 rev early, force 4 %: within
                self.row(8, 1.0, 10.0, 2e-5, 1.04e-6)]  # within
        text = m.judge(rows + [ref], ref, 0.05, list(m.QUANTITIES))
        self.assertIn("0.05 s", text)
        self.assertEqual([r["within"] for r in rows], [True, False, True, True])
        self.assertEqual(m.recommend(rows, m.QUANTITIES)["modes"], 4)
        # The largest below the reference beyond: none, whatever the smaller ones did.
        rows[-1]["max_force"] = 11.0
        m.judge(rows + [ref], ref, 0.05, list(m.QUANTITIES))
        self.assertIsNone(m.recommend(rows, m.QUANTITIES))
        self.assertFalse(rows[-1]["within_max_force"])
        # Not judging the force admits 4 again.
        m.judge(rows + [ref], ref, 0.05, ["first_contact", "orbit_station", "orbit_probe"])
        self.assertEqual(m.recommend(rows, m.QUANTITIES)["modes"], 4)

    def test_contact_in_one_model_only_is_beyond_any_tolerance(self):
        m = self.m
        ref = self.row(20, None, 0.0, 1e-5, 1e-6, speed=None)
        rows = [self.row(1, 1.0, 3.0, 1e-5, 1e-6), self.row(2, None, 0.0, 1e-5, 1e-6, speed=None)]
        m.judge(rows + [ref], ref, 1.0, list(m.QUANTITIES))
        self.assertFalse(rows[0]["within_first_contact"])
        self.assertFalse(rows[0]["within_max_force"])
        self.assertTrue(rows[1]["within"])


class BadInput(unittest.TestCase):
    def one_line(self, r, *words):
        self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
        self.assertEqual(r.stderr.count("\n"), 1, r.stderr)
        self.assertTrue(r.stderr.startswith("rub_truncation.py: "), r.stderr)
        for w in words:
            self.assertIn(w, r.stderr)

    def test_bad_arguments(self):
        self.one_line(tool("--scene", SEAL, "--tolerance", "2"), "--tolerance", "'2'", "(0, 1]")
        self.one_line(tool("--scene", SEAL, "--tolerance", "abc"), "--tolerance", "'abc'", "not a number")
        self.one_line(tool("--scene", SEAL, "--modes", "513"), "--modes", "'513'", "[1, 511]")
        self.one_line(tool("--scene", SEAL, "--modes", "512"), "--modes", "'512'", "[1, 511]")  # the same bound as 513
        self.one_line(tool("--scene", SEAL, "--quantities", "force"), "--quantities", "'force'", "max_force")
        self.one_line(tool("--scene", SEAL, "--set", "rotor_planar_modes=3"), "--set", "--modes")
        self.one_line(tool("--scene", PAPER), "--scene", "no rotor_file")

    def test_a_run_the_runner_refuses_or_that_fails(self):
        r = tool("--scene", SEAL, "--modes", "1", "--set", "friction_coefficient=-1")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("rotor_rub_run refused the run", r.stderr)
        self.assertIn("friction_coefficient", r.stderr)
        r = tool("--scene", SEAL, "--modes", "1", "--set", "max_wall_time_s=1e-4")
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertIn("exit status 7", r.stderr)
        self.assertIn("timed_out", r.stderr)  # the runner's own stderr


if __name__ == "__main__":
    rostest.rosrun(PKG, "rub_truncation", "__main__", sys.argv)  # every TestCase above
