#!/usr/bin/env python3
"""plot_machine.py on a short run of the headless runner (CI style, as
plot_run.py is tested): every picture drawn from rotor_rub_run's CSVs, the
torque panel when RUN.csv has drive_torque and friction_torque and the speed
alone when it has not, and clear errors (exit 2) without the probe geometry
or on a file that is not the runner's."""
import csv
import os
import subprocess
import sys
import unittest

import rostest

from ros_test_support import PAPER_SCENE, find_binary, temp_prefix

PICTURES = ("drive", "probes", "orbit", "bode")


class PlotMachine(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.p = temp_prefix("machine")
        subprocess.run([find_binary("rotor_rub_run"), "--scene", PAPER_SCENE, "--set", "end_time_s=1.5",
                        "--set", "probe_rate_hz=2000", "--set", "probe_noise_V=0.01", "--csv", cls.p + ".csv",
                        "--probes", cls.p + ".p.csv", "--keyphasor", cls.p + ".k.csv", "--summary", cls.p + ".json",
                        "--quiet"], check=True)

    def plot(self, out, csv_path=None, *extra):
        return subprocess.run([find_binary("plot_machine.py"), "--csv", csv_path or self.p + ".csv", "--probes",
                               self.p + ".p.csv", "--keyphasor", self.p + ".k.csv", "--out", out] + list(extra),
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=300)

    def check_pictures(self, out):
        for name in PICTURES:
            path = os.path.join(out, name + ".png")
            self.assertTrue(os.path.exists(path), path)
            self.assertGreater(os.path.getsize(path), 10000, name)

    def test_runner_csvs_without_torque_columns(self):
        # A CSV written before the drive model (no drive_torque, friction_torque): speed only.
        src, dst = self.p + ".csv", temp_prefix("old") + ".csv"
        with open(src) as f, open(dst, "w") as g:
            rows = list(csv.reader(f))
            self.assertEqual(rows[0][-2:], ["drive_torque", "friction_torque"])
            csv.writer(g).writerows(row[:-2] for row in rows)
        out = temp_prefix("pictures")
        r = self.plot(out, dst, "--summary", self.p + ".json")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.check_pictures(out)
        self.assertIn("drive (speed only), probes, orbit, bode", r.stdout)

    def test_torque_columns_are_drawn_when_present(self):
        # RUN.csv as the runner writes it, with the drive's torques.
        dst = self.p + ".csv"
        out = temp_prefix("pictures_torque")
        r = self.plot(out, dst, "--probe-x-angle-rad", "0.785398163397448", "--probe-y-angle-rad",
                      "2.35619449019234", "--probe-sensitivity", "7874")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.check_pictures(out)
        self.assertIn("drive, probes, orbit, bode", r.stdout)

    def test_errors(self):
        out = temp_prefix("pictures_bad")
        r = self.plot(out)  # no geometry
        self.assertEqual(r.returncode, 2)
        self.assertIn("--summary", r.stderr)
        self.assertEqual(r.stderr.count("\n"), 1, r.stderr)
        r = self.plot(out, self.p + ".k.csv", "--summary", self.p + ".json")  # not a run CSV
        self.assertEqual(r.returncode, 2)
        self.assertIn("lacks the column(s) in_contact", r.stderr)


if __name__ == "__main__":
    rostest.rosrun("rotor_rub_sim", "plot_machine", PlotMachine, sys.argv)
