#!/usr/bin/env python3
"""ross_mat_to_yaml.py on a rotor written as ROSS's save_mat writes one (6 DOF
per node, [x, y, z, alpha, beta, theta], the positions as "nodes"): the
rotor file it writes gives rotor_rub_modal the modes of the lateral rotor
that numpy finds (a three-node lumped rotor on anisotropic, cross-coupled,
damped bearings, with gyroscopics, its axial and torsional DOFs with their own
mass and stiffness), and the same rotor with a bearing on a pedestal (a
point mass past the shaft, ROSS's 3 DOF after the nodes'); bad files exit 2
naming what is wrong."""
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


def on_a_pedestal(m, k, c, g):
    """The lumped rotor with its node-0 bearing on a pedestal: a support node
    (x, y after the nodes' DOFs) of 5 kg, joined to node 0 by a spring of
    3e6 N/m and to the ground by 8e6 in x, 6e6 in y."""
    n = 4 * NODES
    grow = lambda a: np.pad(a, ((0, 2), (0, 2)))
    m, k, c, g = grow(m), grow(k), grow(c), grow(g)
    m[n, n] = m[n + 1, n + 1] = 5.0
    for d in (0, 1):
        a, b = d, n + d
        k[a, a] += 3e6
        k[b, b] += 3e6
        k[a, b] -= 3e6
        k[b, a] -= 3e6
    k[n, n] += 8e6
    k[n + 1, n + 1] += 6e6
    return m, k, c, g


def six_with_support(four, axial, torsional):
    """ROSS's order: 6 DOF per node, then [x, y, z] per point mass: the
    pedestal's, and an empty one (ROSS's for a point mass on a shaft node)."""
    size = 6 * NODES + 6
    six = np.zeros((size, size))
    idx = [6 * (a // 4) + LATERAL[a % 4] for a in range(4 * NODES)] + [6 * NODES, 6 * NODES + 1]
    six[np.ix_(idx, idx)] = four
    for node in range(NODES):
        six[6 * node + 2, 6 * node + 2] = axial
        six[6 * node + 5, 6 * node + 5] = torsional
    six[6 * NODES + 2, 6 * NODES + 2] = axial
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
        self.assert_modes_of(out, (m, k, c, g), 4)

    def assert_modes_of(self, rotor_file, matrices, count):
        """rotor_rub_modal's lowest modes at rest of the file are numpy's of the matrices."""
        modal = subprocess.run([find_binary("rotor_rub_modal"), "--rotor", rotor_file, "--modes", str(count)],
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=120)
        self.assertEqual(modal.returncode, 0, modal.stderr)
        got = [float(x) for x in re.findall(r"^\s+\d+\s+([0-9.]+)\s", modal.stdout, re.M)]
        want = damped_frequencies(*matrices, 0.0, count)
        self.assertEqual(len(got), count, modal.stdout)
        for w_got, w_want in zip(got, want):
            # The tool prints 8 decimals; numpy's eigenvalues carry eps times the largest.
            self.assertAlmostEqual(w_got / w_want, 1.0, delta=1e-8)

    def test_a_point_mass_past_the_shaft_is_a_support_node(self):
        m, k, c, g = on_a_pedestal(*lateral_rotor())
        mat = temp_prefix("ross_pedestal") + ".mat"
        scipy.io.savemat(mat, {"M": six_with_support(m, 6.0, 0.02), "K": six_with_support(k, 1e9, 1e5),
                               "C": six_with_support(c, 0.0, 0.0), "G": six_with_support(g, 0.0, 0.0),
                               "nodes": np.array([0.0, 0.2, 0.4])})
        out = temp_prefix("ross_pedestal") + ".yaml"
        r = convert(mat, "--out", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("3 nodes, 6 DOF per node (the reader keeps x, y, alpha, beta), support nodes: 1 (x, y kept)",
                      r.stdout)
        self.assert_modes_of(out, (m, k, c, g), 6)

    def test_bad_files_exit_2_naming_what_is_wrong(self):
        mat = temp_prefix("bad") + ".mat"
        scipy.io.savemat(mat, {"M": np.eye(12), "K": np.eye(12)})
        r = convert(mat, "--out", temp_prefix("bad") + ".yaml")
        self.assertEqual(r.returncode, 2)
        self.assertIn("lacks nodes, C, G", r.stderr)
        scipy.io.savemat(mat, {"M": np.eye(9), "K": np.eye(9), "C": np.eye(9), "G": np.eye(9),
                               "nodes": np.array([0.0, 0.5])})
        r = convert(mat, "--out", temp_prefix("bad") + ".yaml")
        self.assertEqual(r.returncode, 2)
        self.assertIn("M is 9x9 for 2 nodes; accepted: square, 6 DOF per node and 3 per point mass (ROSS's), or 4 DOF"
                      " per node", r.stderr)
        r = convert(os.path.join(os.path.dirname(mat), "missing.mat"), "--out", temp_prefix("bad") + ".yaml")
        self.assertEqual(r.returncode, 2)
        self.assertIn("cannot read", r.stderr)


if __name__ == "__main__":
    rostest.rosrun("rotor_rub_sim", "ross_mat_to_yaml", RossMatToYaml)
