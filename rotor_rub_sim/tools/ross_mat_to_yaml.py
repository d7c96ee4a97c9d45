#!/usr/bin/env python3
"""ross_mat_to_yaml.py: a rotor's matrices as ROSS's Rotor.save_mat writes them
(a MATLAB file of M, K, C, G and nodes, 6 DOF per node) to the rotor file's
`matrices` map (docs/rotors.md), each matrix by its nonzero entries (an FE
rotor's matrices are banded: a 51-node rotor's read in a few hundredths of a
second, its dense rows in half a second), every entry in the shortest digits
that read back as the same double. The 6 DOF per node stay as they are:
the rotor file reader drops the axial and torsional ones, after checking that
nothing couples them to the lateral ones. Add the stations (rub_station,
unbalances, probes) to the file it writes.

  rosrun rotor_rub_sim ross_mat_to_yaml.py rig.mat --out rig.yaml

K and C are ROSS's at the speed save_mat was given (speed-dependent bearings
are evaluated there); G is per unit speed. Exit status: 0 ok; 2 bad input."""
import argparse
import sys

import numpy as np
import scipy.io

KEYS = ("M", "K", "C", "G")


def fail(msg):
    print("ross_mat_to_yaml.py: " + msg, file=sys.stderr)
    sys.exit(2)


def read(path):
    """The nodes' positions and the four matrices of a save_mat file."""
    try:
        data = scipy.io.loadmat(path)
    except (OSError, ValueError) as e:
        fail("cannot read '%s' as a MATLAB file: %s" % (path, e))
    missing = [k for k in ("nodes",) + KEYS if k not in data]
    if missing:
        fail("'%s' lacks %s; accepted: the fields ROSS's save_mat writes (M, K, C, G, nodes)"
             % (path, ", ".join(missing)))
    nodes = np.asarray(data["nodes"], dtype=float).ravel()
    matrices = {k: np.asarray(data[k], dtype=float) for k in KEYS}
    for k, m in matrices.items():
        if m.ndim != 2 or m.shape[0] != m.shape[1] or m.shape[0] not in (4 * len(nodes), 6 * len(nodes)):
            fail("'%s': %s is %s for %d nodes; accepted: square, 4 or 6 DOF per node"
                 % (path, k, "x".join(map(str, m.shape)), len(nodes)))
        if not np.all(np.isfinite(m)):
            fail("'%s': %s has an entry that is not finite" % (path, k))
    return nodes, matrices


def number(x):
    return repr(float(x))  # the shortest string that reads back as the same double


def yaml_text(nodes, matrices, source):
    lines = ["# From %s (ROSS's Rotor.save_mat) by ross_mat_to_yaml.py; add the stations:" % source,
             "# rub_station: {node: N, contact_radius_m: R}, unbalances, probes (docs/rotors.md).",
             "matrices:",
             "  nodes: [%s]" % ", ".join(number(z) for z in nodes)]
    for k in KEYS:
        m = matrices[k]
        rows, cols = np.nonzero(m)
        lines += ["  %s:" % k, "    size: %d" % m.shape[0], "    nonzeros:" + ("" if len(rows) else " []")]
        lines += ["      - [%d, %d, %s]" % (i, j, number(m[i, j])) for i, j in zip(rows, cols)]
    return "\n".join(lines) + "\n"


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("mat", help="the .mat file ROSS's Rotor.save_mat wrote")
    p.add_argument("--out", required=True, help="the rotor file (YAML) to write")
    args = p.parse_args(argv)
    nodes, matrices = read(args.mat)
    try:
        with open(args.out, "w") as f:
            f.write(yaml_text(nodes, matrices, args.mat))
    except OSError as e:
        fail("cannot write '%s': %s" % (args.out, e))
    dofs = matrices["M"].shape[0] // len(nodes)
    print("%s: %d nodes, %d DOF per node%s" % (args.out, len(nodes), dofs,
                                               " (the reader keeps x, y, alpha, beta)" if dofs == 6 else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
