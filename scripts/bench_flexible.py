#!/usr/bin/python3
"""The cost of a flexible rotor's run against the number of modes kept: the
seal-rub run-up (config/seal_rub_runup.yaml) at each rotor_planar_modes, each
run --repeats times by rotor_rub_run (the median wall time of its own
integration timer), with the contact's quantities beside it, printed as a
table. With --page, also written into docs/benchmarks.md between
<!-- BEGIN GENERATED: flexible --> and <!-- END GENERATED: flexible -->, with
the date, the machine and the command (the page's figures are the last run's,
never typed in).

usage: bench_flexible.py RUNNER [--modes 1 2 4 ...] [--repeats N] [--method M]
                         [--scene FILE] [--page docs/benchmarks.md]"""
import argparse
import datetime
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))


def run(runner, scene, modes, method):
    with tempfile.NamedTemporaryFile(suffix=".json") as f:
        subprocess.run([runner, "--scene", scene, "--set", "rotor_planar_modes=%d" % modes, "--set",
                        "method=" + method, "--summary", f.name, "--quiet"], check=True)
        return json.load(open(f.name))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runner", help="rotor_rub_run")
    ap.add_argument("--scene", default=os.path.join(ROOT, "config", "seal_rub_runup.yaml"))
    ap.add_argument("--modes", type=int, nargs="+", default=[1, 2, 4, 8, 12, 16, 20])
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--method", default="switching")
    ap.add_argument("--page", help="write the table into this page (docs/benchmarks.md)")
    a = ap.parse_args(argv)
    if a.repeats < 1 or any(m < 1 for m in a.modes):
        sys.exit("bench_flexible: --repeats and --modes must be >= 1")
    head = "%6s %5s %10s %10s %9s %11s %9s %11s %14s" % ("modes", "coord", "steps", "rhs", "wall_ms", "first_s",
                                                       "max_Fn_N", "touchdowns", "last_end_s")
    lines = [head]
    for m in a.modes:
        runs = [run(a.runner, a.scene, m, a.method) for _ in range(a.repeats)]
        s = runs[0]
        wall_ms = 1e3 * statistics.median(r["stats"]["wall_time_s"] for r in runs)
        lines.append("%6d %5d %10d %10d %9.1f %11.6f %9.3f %11d %14.6f" % (
            m, 2 * m, s["stats"]["steps"], s["stats"]["rhs_evals"], wall_ms, s["first_contact_s"],
            s["max_normal_force_N"], s["stats"]["touchdowns"], s["last_contact_end_s"]))
        print(lines[-1] if len(lines) > 2 else "\n".join(lines), flush=True)
    if a.page:
        cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")),
                   "unknown CPU")
        machine = "%d cores (%s), %s %s" % (os.cpu_count(), cpu, platform.system(), platform.release())
        command = "scripts/bench_flexible.py $WS/devel/lib/rotor_rub_sim/rotor_rub_run --repeats %d --method %s " \
                  "--modes %s --page docs/benchmarks.md" % (a.repeats, a.method, " ".join(map(str, a.modes)))
        block = ["Written by `scripts/bench_flexible.py` on %s UTC, on %s (%s, scene %s; wall: the median of "
                 "%d runs):" % (datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M"), machine, a.method,
                                os.path.relpath(a.scene, ROOT), a.repeats), "", "    " + command, ""]
        block += ["    " + l for l in lines]
        text = open(a.page).read()
        begin, stop = "<!-- BEGIN GENERATED: flexible -->", "<!-- END GENERATED: flexible -->"
        if begin not in text or stop not in text:
            sys.exit("bench_flexible: %s has no '%s' ... '%s' block" % (a.page, begin, stop))
        before, rest = text.split(begin, 1)
        after = rest.split(stop, 1)[1]
        open(a.page, "w").write(before + begin + "\n" + "\n".join(block) + "\n" + stop + after)


if __name__ == "__main__":
    main()
