#!/usr/bin/env python3
"""ross_mat_to_yaml.py on a rotor written as ROSS's save_mat writes one (6 DOF
per node, [x, y, z, alpha, beta, theta], the positions as "nodes"): the
rotor file it writes gives rotor_rub_modal the modes of the lateral rotor
that numpy finds (a three-node lumped rotor on anisotropic, cross-coupled,
damped bearings, with gyroscopics, its axial and torsional DOFs with their own
mass and stiffness); bad files exit 2 naming what is wrong."""
import os
import re
import subprocess
import unittest

import numpy as np
import rostest
import scipy.io

from ros_test_support import find_binary, temp_prefix

NODES = 3
LATERAL = [0, 1, 3, 4]  # x, y, alpha, beta among ROSS's 6


def lateral_rotor():
    """M, K, C, G of a lumped rotor in 4 DOF per node [x, y, alpha, beta]."""
    n = 4 * NODES
    m, k, c, g = (np.zeros((n, n)) for _ in range(4))
    for node in range(NODES):
        i = 4 * node
        m[i:i + 4, i:i + 4] = np.diag([2.0, 2.0, 0.01, 0.01])
        g[i + 2, i + 3], g[i + 3, i + 2] = 0.02, -0.02  # I_p couples the tilts
    for node in range(NODES - 1):  # springs between neighbours, in x, y and the tilts
        for d, stiff in ((0, 4e6), (1, 4e6), (2, 2e4), (3, 2e4)):
            a, b = 4 * node + d, 4 * (node + 1) + d
            k[a, a] += stiff
            k[b, b] += stiff
            k[a, b] -= stiff
            k[b, a] -= stiff
    for node in (0, NODES - 1):  # bearings: kyy/kxx = 10, cross-coupled, damped; holding the tilts
        x, y = 4 * node, 4 * node + 1
        k[x + 2, x + 2] += 5e3
        k[x + 3, x + 3] += 5e3
        k[x, x] += 1e6
        k[y, y] += 1e7
        k[x, y] += 2.5e6
        k[y, x] -= 2e5
        c[x, x] += 300.0
        c[y, y] += 500.0
    return m, k, c, g


def six_dof(four, axial, torsional):
    six = np.zeros((6 * NODES, 6 * NODES))
    idx = [6 * (a // 4) + LATERAL[a % 4] for a in range(4 * NODES)]
    six[np.ix_(idx, idx)] = four
    for node in range(NODES):
        six[6 * node + 2, 6 * node + 2] = axial
        six[6 * node + 5, 6 * node + 5] = torsional
    return six


def damped_frequencies(m, k, c, g, speed, count):
    n = m.shape[0]
    minv = np.linalg.inv(m)
    a = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ k, -minv @ (c + speed * g)]])
    lam = np.linalg.eigvals(a)
    return sorted(l.imag for l in lam if l.imag > 1e-8 * abs(l))[:count]


def convert(*args):
    return subprocess.run([find_binary("ross_mat_to_yaml.py")] + list(args), stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, timeout=60)


class RossMatToYaml(unittest.TestCase):
    def test_the_file_gives_the_lateral_rotors_modes(self):
        m, k, c, g = lateral_rotor()
        mat = temp_prefix("ross") + ".mat"
        scipy.io.savemat(mat, {"M": six_dof(m, 6.0, 0.02), "K": six_dof(k, 1e9, 1e5), "C": six_dof(c, 0.0, 0.0),
                               "G": six_dof(g, 0.0, 0.0), "nodes": np.array([0.0, 0.2, 0.4])})
        out = temp_prefix("ross") + ".yaml"
        r = convert(mat, "--out", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("3 nodes, 6 DOF per node", r.stdout)
        modal = subprocess.run([find_binary("rotor_rub_modal"), "--rotor", out, "--modes", "4"],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=120)
        self.assertEqual(modal.returncode, 0, modal.stderr)
        got = [float(x) for x in re.findall(r"^\s+\d+\s+([0-9.]+)\s", modal.stdout, re.M)]
        want = damped_frequencies(m, k, c, g, 0.0, 4)
        self.assertEqual(len(got), 4, modal.stdout)
        for w_got, w_want in zip(got, want):
            # The tool prints 8 decimals; numpy's eigenvalues carry eps times the largest.
            self.assertAlmostEqual(w_got / w_want, 1.0, delta=1e-8)

    def test_bad_files_exit_2_naming_what_is_wrong(self):
        mat = temp_prefix("bad") + ".mat"
        scipy.io.savemat(mat, {"M": np.eye(12), "K": np.eye(12)})
        r = convert(mat, "--out", temp_prefix("bad") + ".yaml")
        self.assertEqual(r.returncode, 2)
        self.assertIn("lacks nodes, C, G", r.stderr)
        scipy.io.savemat(mat, {"M": np.eye(10), "K": np.eye(10), "C": np.eye(10), "G": np.eye(10),
                               "nodes": np.array([0.0, 0.5])})
        r = convert(mat, "--out", temp_prefix("bad") + ".yaml")
        self.assertEqual(r.returncode, 2)
        self.assertIn("M is 10x10 for 2 nodes; accepted: square, 4 or 6 DOF per node", r.stderr)
        r = convert(os.path.join(os.path.dirname(mat), "missing.mat"), "--out", temp_prefix("bad") + ".yaml")
        self.assertEqual(r.returncode, 2)
        self.assertIn("cannot read", r.stderr)


if __name__ == "__main__":
    rostest.rosrun("rotor_rub_sim", "ross_mat_to_yaml", RossMatToYaml)
