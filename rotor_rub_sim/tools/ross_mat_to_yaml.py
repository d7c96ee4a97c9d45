#!/usr/bin/env python3
"""ross_mat_to_yaml.py: a rotor's matrices as ROSS's Rotor.save_mat writes them
(a MATLAB file of M, K, C, G and nodes, 6 DOF per node) to the rotor file's
`matrices` map (docs/rotors.md), each matrix by its nonzero entries (an FE
rotor's matrices are banded: a 51-node rotor's read in a few hundredths of a
second, its dense rows in half a second), every entry in the shortest digits
that read back as the same double. The 6 DOF per node stay as they are:
the rotor file reader drops the axial and torsional ones, after checking that
nothing couples them to the lateral ones. ROSS's point masses past the
shaft's last node (pedestals, joined to the shaft by bearings' n_link) add 3
DOF each (x, y, z) after the nodes': written as support_nodes (ROSS gives a
point mass on a shaft node 3 DOF too, left empty: dropped). Add the stations (rub_station,
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
    size = matrices["M"].shape[0] if matrices["M"].ndim == 2 else -1
    supports = support_nodes(size, len(nodes))
    for k, m in matrices.items():
        if m.ndim != 2 or m.shape[0] != m.shape[1] or m.shape[0] != size or supports is None:
            fail("'%s': %s is %s for %d nodes; accepted: square, 6 DOF per node and 3 per point mass (ROSS's),"
                 " or 4 DOF per node" % (path, k, "x".join(map(str, m.shape)), len(nodes)))
        if not np.all(np.isfinite(m)):
            fail("'%s': %s has an entry that is not finite" % (path, k))
    if size != 4 * len(nodes):
        matrices, supports = drop_empty_supports(len(nodes), matrices, supports)
    return nodes, matrices, supports


def support_nodes(size, nodes):
    """The support nodes in a matrix of `size` rows for `nodes` shaft nodes:
    ROSS's 6 DOF per node and 3 (x, y, z) per point mass, or exactly 4 DOF per
    node (an older ROSS's, none); None when neither fits."""
    extra = size - 6 * nodes
    if extra >= 0 and extra % 3 == 0:
        return extra // 3
    return 0 if size == 4 * nodes else None


def drop_empty_supports(nodes, matrices, supports):
    """ROSS gives every point mass 3 DOF after the nodes', and those of a point
    mass on a shaft node stay empty (its mass is on the node's): a support
    DOF with no entry in any matrix is dropped. Returns the matrices and the
    support nodes that have entries."""
    keep = list(range(6 * nodes))
    used = 0
    for k in range(supports):
        dofs = [6 * nodes + 3 * k + d for d in range(3)]
        if any(np.any(m[dofs, :]) or np.any(m[:, dofs]) for m in matrices.values()):
            keep += dofs
            used += 1
    if used == supports:
        return matrices, supports
    return {k: m[np.ix_(keep, keep)] for k, m in matrices.items()}, used


def number(x):
    return repr(float(x))  # the shortest string that reads back as the same double


def yaml_text(nodes, matrices, supports, source):
    lines = ["# From %s (ROSS's Rotor.save_mat) by ross_mat_to_yaml.py; add the stations:" % source,
             "# rub_station: {node: N, contact_radius_m: R}, unbalances, probes (docs/rotors.md).",
             "matrices:",
             "  nodes: [%s]" % ", ".join(number(z) for z in nodes)]
    if supports:
        lines.append("  support_nodes: %d" % supports)
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
    nodes, matrices, supports = read(args.mat)
    try:
        with open(args.out, "w") as f:
            f.write(yaml_text(nodes, matrices, supports, args.mat))
    except OSError as e:
        fail("cannot write '%s': %s" % (args.out, e))
    six = matrices["M"].shape[0] == 6 * len(nodes) + 3 * supports
    print("%s: %d nodes, %d DOF per node%s%s" % (
        args.out, len(nodes), 6 if six else 4, " (the reader keeps x, y, alpha, beta)" if six else "",
        ", support nodes: %d (x, y kept)" % supports if supports else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
