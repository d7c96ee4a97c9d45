#!/usr/bin/python3
"""The cost of a flexible rotor's run against the number of modes kept: the
seal-rub run-up (config/seal_rub_runup.yaml, or --scene) at each
rotor_planar_modes, each run --repeats times by rotor_rub_run (the median
wall time of its own integration timer), with the contact's quantities beside
it, printed as a table. With several --method (METHOD or METHOD:INTEGRATOR),
one column group per solver: its steps, its wall time and that time over its
time at the first mode count; METHOD[:INTEGRATOR]@N runs that solver up to N
planar modes only (its cells above read "-": an explicit scheme at a large
rotor's full model would take hours); the touchdowns are then the first
unbounded solver's. With --page, also written into
docs/benchmarks.md between <!-- BEGIN GENERATED: NAME --> and <!-- END
GENERATED: NAME --> (--block, default flexible), with the date, the machine
and the command (the page's figures are the last run's, never typed in).

With --penalty-stiffness K [K ...], instead: the penalty method on dopri5 and
on rosenbrock4 at each contact stiffness K [N/m] (the scene's modes), each
run's largest distance from the dopri5 run's station on the samples beside
it (with --page, into the block --block names: docs/benchmarks.md holds none
of these).

usage: bench_flexible.py RUNNER [--modes 1 2 4 ...] [--repeats N] [--method M[:I][@N] ...]
                         [--penalty-stiffness K ...] [--scene FILE]
                         [--page docs/benchmarks.md] [--block NAME]"""
import csv
import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile

from doc_blocks import machine, now_utc, write_block

ROOT = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))


def run(runner, scene, sets, samples_csv=None):
    with tempfile.NamedTemporaryFile(suffix=".json") as f:
        cmd = [runner, "--scene", scene, "--summary", f.name, "--quiet"]
        for s in sets:
            cmd += ["--set", s]
        if samples_csv:
            cmd += ["--csv", samples_csv]
        subprocess.run(cmd, check=True)
        return json.load(open(f.name))


def station(samples_csv):
    return [(float(r["x_r"]), float(r["y_r"])) for r in csv.DictReader(open(samples_csv))]


def penalty_rows(a):
    """The penalty method on dopri5 and rosenbrock4 at each contact stiffness."""
    lines = ["%8s %12s %10s %10s %9s %9s %14s %12s" % ("k_c_N_m", "integrator", "steps", "rhs", "wall_ms",
                                                       "max_Fn_N", "last_end_s", "from_dopri5_m")]
    print(lines[0], flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        for kc in a.penalty_stiffness:
            reference = None
            for integrator in ("dopri5", "rosenbrock4"):
                sets = ["method=penalty", "integrator=" + integrator, "contact_stiffness_N_per_m=%g" % kc]
                samples = os.path.join(tmp, "samples.csv")
                runs = [run(a.runner, a.scene, sets, samples if i == 0 else None) for i in range(a.repeats)]
                orbit = station(samples)
                if reference is None:
                    reference = orbit
                gap = max(math.hypot(p[0] - q[0], p[1] - q[1]) for p, q in zip(orbit, reference))
                if len(orbit) != len(reference):
                    gap = float("nan")
                s = runs[0]
                wall_ms = 1e3 * statistics.median(r["stats"]["wall_time_s"] for r in runs)
                lines.append("%8.0e %12s %10d %10d %9.1f %9.3f %14.6f %12.2e" % (
                    kc, integrator, s["stats"]["steps"], s["stats"]["rhs_evals"], wall_ms,
                    s["max_normal_force_N"], s["last_contact_end_s"], gap))
                print(lines[-1], flush=True)
    return lines


def solver_sets(solver):
    """--set arguments of METHOD or METHOD:INTEGRATOR (an @N bound aside)."""
    method, _, integrator = solver.partition("@")[0].partition(":")
    return ["method=" + method] + (["integrator=" + integrator] if integrator else [])


def solver_bound(solver):
    """The most planar modes METHOD[:INTEGRATOR]@N runs (None: no bound)."""
    _, at, bound = solver.partition("@")
    if not at:
        return None
    if not bound.isdigit() or int(bound) < 1:
        sys.exit("bench_flexible: --method %s: the bound after @ must be an integer >= 1" % solver)
    return int(bound)


def solvers_rows(a):
    """Each solver's run at each number of planar modes: steps, wall, and the
    wall over the first mode count's (the cost's growth)."""
    head = "%6s %5s %11s" % ("modes", "coord", "touchdowns")
    for solver in a.method:
        head += " | %28s" % (solver + ": steps, ms, x")
    lines = [head]
    print(head, flush=True)
    first = {}
    # The touchdowns column: the first unbounded solver's (else the first that
    # ran in the row), so that its source stays one solver where it can.
    counter = next((solver for solver in a.method if solver_bound(solver) is None), None)
    for m in a.modes:
        touchdowns = None
        cells = []
        for solver in a.method:
            bound = solver_bound(solver)
            if bound is not None and m > bound:
                cells.append(" | %10s %10s %7s" % ("-", "-", "-"))
                continue
            sets = ["rotor_planar_modes=%d" % m] + solver_sets(solver)
            runs = [run(a.runner, a.scene, sets) for _ in range(a.repeats)]
            s = runs[0]
            wall_ms = 1e3 * statistics.median(r["stats"]["wall_time_s"] for r in runs)
            first.setdefault(solver, wall_ms)
            if solver == counter or (touchdowns is None and counter is None):
                touchdowns = s["stats"]["touchdowns"]
            cells.append(" | %10d %10.1f %6.0fx" % (s["stats"]["steps"], wall_ms, wall_ms / first[solver]))
        line = "%6d %5d %11s" % (m, 2 * m, "-" if touchdowns is None else touchdowns) + "".join(cells)
        lines.append(line)
        print(line, flush=True)
    return lines


def mode_rows(a):
    """The method's run at each number of planar modes."""
    if len(a.method) > 1 or solver_bound(a.method[0]) is not None:
        return solvers_rows(a)
    head = "%6s %5s %10s %10s %9s %11s %9s %11s %14s" % ("modes", "coord", "steps", "rhs", "wall_ms", "first_s",
                                                       "max_Fn_N", "touchdowns", "last_end_s")
    lines = [head]
    for m in a.modes:
        sets = ["rotor_planar_modes=%d" % m] + solver_sets(a.method[0])
        runs = [run(a.runner, a.scene, sets) for _ in range(a.repeats)]
        s = runs[0]
        wall_ms = 1e3 * statistics.median(r["stats"]["wall_time_s"] for r in runs)
        lines.append("%6d %5d %10d %10d %9.1f %11.6f %9.3f %11d %14.6f" % (
            m, 2 * m, s["stats"]["steps"], s["stats"]["rhs_evals"], wall_ms, s["first_contact_s"],
            s["max_normal_force_N"], s["stats"]["touchdowns"], s["last_contact_end_s"]))
        print(lines[-1] if len(lines) > 2 else "\n".join(lines), flush=True)
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runner", help="rotor_rub_run")
    ap.add_argument("--scene", default=os.path.join(ROOT, "config", "seal_rub_runup.yaml"))
    ap.add_argument("--modes", type=int, nargs="+", default=[1, 2, 4, 8, 12, 16, 20])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--method", nargs="+", default=["switching"], metavar="M[:I][@N]",
                    help="solvers: a method, or method:integrator; several give one column group each; "
                         "@N: up to N planar modes only")
    ap.add_argument("--penalty-stiffness", type=float, nargs="+", metavar="K",
                    help="the penalty method on dopri5 and rosenbrock4 at these contact stiffnesses [N/m]")
    ap.add_argument("--page", help="write the table into this page (docs/benchmarks.md)")
    ap.add_argument("--block", help="the page's block to write (default: flexible)")
    a = ap.parse_args(argv)
    if a.repeats < 1 or any(m < 1 for m in a.modes):
        sys.exit("bench_flexible: --repeats and --modes must be >= 1")
    for solver in a.method:
        bound = solver_bound(solver)
        if bound is not None and bound < min(a.modes):
            sys.exit("bench_flexible: --method %s: the bound is below every --modes count (%d)" % (solver, min(a.modes)))
    if a.penalty_stiffness and any(not (k > 0.0) for k in a.penalty_stiffness):
        sys.exit("bench_flexible: --penalty-stiffness must be > 0")
    if a.penalty_stiffness and a.page and not a.block:
        sys.exit("bench_flexible: --penalty-stiffness with --page needs --block NAME")
    lines = penalty_rows(a) if a.penalty_stiffness else mode_rows(a)
    if a.page:
        what = "--penalty-stiffness %s" % " ".join("%g" % k for k in a.penalty_stiffness) if a.penalty_stiffness \
            else "--method %s --modes %s" % (" ".join(a.method), " ".join(map(str, a.modes)))
        scene = os.path.relpath(a.scene, ROOT)
        if scene != "config/seal_rub_runup.yaml":
            what = "--scene %s %s" % (scene, what)
        name = a.block or "flexible"
        if a.block:
            what += " --block " + a.block
        command = "scripts/bench_flexible.py $WS/devel/lib/rotor_rub_sim/rotor_rub_run --repeats %d %s " \
                  "--page docs/benchmarks.md" % (a.repeats, what)
        block = ["Written by `scripts/bench_flexible.py` on %s UTC, on %s (%s, scene %s; wall: the median of "
                 "%d runs):" % (now_utc(), machine(), "penalty" if a.penalty_stiffness else ", ".join(a.method),
                                scene, a.repeats), "", "    " + command, ""]
        block += ["    " + l for l in lines]
        write_block(a.page, name, block, "bench_flexible")

if __name__ == "__main__":
    main()
