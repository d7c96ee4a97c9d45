#!/usr/bin/python3
"""Writes the measured tables of docs/benchmarks.md from the CSVs the measuring
scripts leave in docs/data/, each between <!-- BEGIN GENERATED: NAME --> and
<!-- END GENERATED: NAME -->:

  bench_rows         bench.csv (rotor_rub_bench --csv, scripts/make_charts.sh): every
                     method and integrator at rtol 1e-3, 1e-6 and 1e-9, and CVODE's
  table2             paper_table2.csv and work_precision.csv (scripts/make_charts.sh):
                     the paper's Table 2 beside ours, and each pair's loosest rtol
                     within 1e-6 m
  penalty_stiffness  stability_penalty_adaptive.csv (scripts/make_stability.sh): the
                     penalty method's error and cost against its contact stiffness
  stick_slip         stick_slip_cost.csv (scripts/make_charts.sh): every method and
                     integrator at constant speeds and frictions where the rotor rolls

Each block opens with a line saying what wrote it, from which file, and when and
where that file was measured. --measured-now (the measuring scripts pass it, right
after the measurement) stamps the present time and machine; without it the
block's stamp stays (the same measurement, rewritten). With --check, writes
nothing and exits 1 when a block's table differs from what the CSVs give (the
test command runs it on the committed data).

usage: gen_bench_tables.py [--check] [--measured-now] --data DIR --page PAGE BLOCK..."""
import argparse
import csv
import math
import os
import sys

from doc_blocks import block, machine, now_utc, replace_block

COMPLETED = ("ok", "inaccurate")  # runs that reached the end (rotor_rub_sweep's statuses)
METHOD_ORDER = {"switching": 0, "iteration": 1, "penalty": 2, "cvode": 3}
# The paper's Table 2 (its MATLAB ode45 runs of 2002): time [s], derivatives
# and iteration shares, steps.
PAPER_TABLE2 = {
    "penalty": ("1123", "62 %", "0 %", "90 459"),
    "switching": ("45", "64 %", "1 %", "1 857"),
    "iteration": ("1050", "19 %", "65 %", "8 040"),
}


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def fnum(row, key):
    try:
        return float(row[key])
    except (KeyError, TypeError, ValueError):
        return math.nan


def ms(seconds):
    """A time in ms to three figures (whole ms from 100 up): 0.740, 3.00, 183, 5360."""
    v = 1e3 * seconds
    return "%.0f" % v if v >= 99.95 else "%#.3g" % v


def sci(v):
    """1e+09 -> 1e9, 2.5e+09 -> 2.5e9."""
    mantissa, exponent = ("%.1e" % v).split("e")
    return "%se%d" % (mantissa.rstrip("0").rstrip("."), int(exponent))


def pair_order(pair):
    """(method, integrator) pairs in the docs' order: switching, iteration, penalty, CVODE."""
    return (METHOD_ORDER.get(pair[0], 9),) + tuple(pair)


def pairs(rows):
    return sorted({(r["method"], r["integrator"]) for r in rows}, key=pair_order)


def percent(row, key):
    v = fnum(row, key)
    return "%.0f" % (100 * v) if math.isfinite(v) else "-"


def bench_rows(data):
    rows = read_csv(os.path.join(data, "bench.csv"))
    shown = [r for r in rows if any(math.isclose(fnum(r, "rtol"), t) for t in (1e-3, 1e-6, 1e-9))]
    lines = ["| method | integrator | rtol / atol | wall / quiet [ms] | steps (+rej) | RHS evals | "
             "rhs / iter / evt / out % | max \\|dr_r\\| [m] |",
             "|---|---|---|---|---|---|---|---|"]
    for r in sorted(shown, key=lambda r: (pair_order((r["method"], r["integrator"])), -fnum(r, "rtol"))):
        if r["method"] == "cvode":  # timed without output: one time, no shares
            wall = ms(fnum(r, "quiet_wall_time_s"))
            shares = ""
        else:
            wall = "%s / %s" % (ms(fnum(r, "wall_time_s")), ms(fnum(r, "quiet_wall_time_s")))
            shares = " / ".join(percent(r, k) for k in ("rhs_share", "iteration_share", "event_share", "output_share"))
        error = "%.1e" % fnum(r, "max_rotor_err_m")
        if r["status"] != "ok":
            error += " (`%s`)" % r["status"]
        lines.append("| %s | %s | %s / %s | %s | %s (+%s) | %s | %s | %s |" % (
            r["method"], r["integrator"], r["rtol"], r["atol"], wall, r["steps"], r["rejected_steps"], r["rhs_evals"],
            shares, error))
    return lines


def table2(data):
    t2 = read_csv(os.path.join(data, "paper_table2.csv"))
    wp = read_csv(os.path.join(data, "work_precision.csv"))
    lines = ["| method | paper: time [s] | paper: derivatives / iteration | paper: steps | ours: time [ms] | "
             "ours: derivatives / iteration | ours: steps (+rejected) | ours: max error [m] |",
             "|---|---|---|---|---|---|---|---|"]
    for r in t2:
        p = PAPER_TABLE2.get(r["method"], ("", "", "", ""))
        lines.append("| %s | %s | %s / %s | %s | %.2f | %s %% / %s %% | %s (+%s) | %.1e |" % (
            r["method"], p[0], p[1], p[2], p[3], 1e3 * fnum(r, "wall_time_s"), percent(r, "rhs_share"),
            percent(r, "iteration_share"), r["steps"], r["rejected_steps"], fnum(r, "max_rotor_err_m")))
    lines += ["", "The loosest tolerance at which each method and integrator's max |r_r - r_r,ref| is within",
              "1e-6 m (the work-precision sweep, `config/sweeps/work_precision.yaml`; atol = 1e-3 rtol):", "",
              "| method | integrator | rtol | time [ms] | steps (+rejected) | RHS evaluations | max error [m] |",
              "|---|---|---|---|---|---|---|"]
    for method, integrator in pairs(wp):
        runs = [r for r in wp if (r["method"], r["integrator"]) == (method, integrator) and r["status"] in COMPLETED]
        within = [r for r in runs if fnum(r, "max_rotor_err_m") <= 1e-6]
        if not within:
            best = min(runs, key=lambda r: fnum(r, "max_rotor_err_m"), default=None)
            text = "none" if best is None else "%.1e m (rtol %s, k_c %s N/m)" % (
                fnum(best, "max_rotor_err_m"), best["rtol"], sci(fnum(best, "contact_stiffness_N_per_m")))
            lines.append("| %s | %s | none within 1e-6 m | | | | best %s |" % (method, integrator, text))
            continue
        r = max(within, key=lambda r: fnum(r, "rtol"))
        lines.append("| %s | %s | %s | %.2f | %s (+%s) | %s | %.1e |" % (
            method, integrator, r["rtol"], 1e3 * fnum(r, "wall_time_s"), r["steps"], r["rejected_steps"],
            r["rhs_evals"], fnum(r, "max_rotor_err_m")))
    return lines


def penalty_stiffness(data):
    rows = [r for r in read_csv(os.path.join(data, "stability_penalty_adaptive.csv")) if r["method"] == "penalty"]
    integrators = sorted({r["integrator"] for r in rows})
    lines = ["| k_c [N/m] | " + " | ".join("%s: error / time (steps)" % i for i in integrators) + " |",
             "|---|" + "---|" * len(integrators)]
    for k in sorted({fnum(r, "contact_stiffness_N_per_m") for r in rows}):
        cells = []
        for i in integrators:
            r = next((r for r in rows if r["integrator"] == i and fnum(r, "contact_stiffness_N_per_m") == k), None)
            if r is None:
                cells.append("")
            elif r["status"] not in COMPLETED:
                cells.append("`%s` after %s ms" % (r["status"], ms(fnum(r, "wall_time_s"))))
            else:
                cells.append("%.1e m%s / %s ms (%s)" % (
                    fnum(r, "max_rotor_err_m"), "" if r["status"] == "ok" else " (`%s`)" % r["status"],
                    ms(fnum(r, "wall_time_s")), r["steps"]))
        lines.append("| %s | %s |" % (sci(k), " | ".join(cells)))
    return lines


def settings(row):
    """rotor_rub_sweep's other_settings, 'key=value;...', as a dict."""
    return dict(kv.split("=", 1) for kv in row["other_settings"].split(";") if "=" in kv)


def stick_slip(data):
    rows = read_csv(os.path.join(data, "stick_slip_cost.csv"))
    if any("initial_speed_rad_per_s" not in settings(r) for r in rows):
        raise KeyError("initial_speed_rad_per_s in other_settings")
    scene = lambda r: (fnum(settings(r), "initial_speed_rad_per_s"), fnum(r, "friction_coefficient"))  # noqa: E731
    scenes = sorted({scene(r) for r in rows})
    lines = ["| method | integrator | " + " | ".join("%g rad/s, f %g" % sc for sc in scenes) + " |",
             "|---|---|" + "---|" * len(scenes)]
    for method, integrator in pairs(rows):
        cells = []
        for sc in scenes:
            r = next((r for r in rows if (r["method"], r["integrator"]) == (method, integrator) and scene(r) == sc),
                     None)
            if r is None:
                cells.append("")
            elif r["status"] not in COMPLETED:
                cells.append("`%s`" % r["status"])
            else:
                cells.append("%s ms, %.1e m%s" % (ms(fnum(r, "wall_time_s")), fnum(r, "max_rotor_err_m"),
                                                  "" if r["status"] == "ok" else " (`%s`)" % r["status"]))
        lines.append("| %s | %s | %s |" % (method, integrator, " | ".join(cells)))
    # The contact and its rolling, as the runs saw them (which the pointwise
    # error of a drifting whirl does not show): the rigid methods' spread,
    # and the penalty method's, whose bore its penetration enlarges.
    for what, key in (("contact", "contact_time_s"), ("rolling (stick)", "stick_time_s")):
        for label, methods in (("switching, iteration", ("switching", "iteration")), ("penalty", ("penalty",))):
            cells = []
            for sc in scenes:
                v = [fnum(r, key) for r in rows
                     if scene(r) == sc and r["method"] in methods and r["status"] in COMPLETED]
                cells.append("%.4f to %.4f s" % (min(v), max(v)) if v else "")
            lines.append("| %s time | %s | %s |" % (what, label, " | ".join(cells)))
    return lines


BLOCKS = {
    "bench_rows": (["bench.csv"], "scripts/make_charts.sh", bench_rows),
    "table2": (["paper_table2.csv", "work_precision.csv"], "scripts/make_charts.sh", table2),
    "penalty_stiffness": (["stability_penalty_adaptive.csv"], "scripts/make_stability.sh", penalty_stiffness),
    "stick_slip": (["stick_slip_cost.csv"], "scripts/make_charts.sh", stick_slip),
}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--check", action="store_true", help="write nothing; exit 1 when a table differs")
    ap.add_argument("--measured-now", action="store_true", help="stamp the present time and machine")
    ap.add_argument("--data", required=True, help="the CSVs' directory (docs/data)")
    ap.add_argument("--page", required=True, help="the page (docs/benchmarks.md)")
    ap.add_argument("blocks", nargs="+", choices=sorted(BLOCKS), metavar="BLOCK",
                    help="one of: " + ", ".join(sorted(BLOCKS)))
    a = ap.parse_args(argv)
    old = open(a.page).read()
    new = old
    for name in a.blocks:
        files, script, make = BLOCKS[name]
        try:
            current = block(new, name)
        except ValueError as e:
            sys.exit("gen_bench_tables: %s has %s" % (a.page, e))
        try:
            table = make(a.data)
        except (OSError, KeyError) as e:
            sys.exit("gen_bench_tables: block %s: cannot read %s in %s: %s" % (name, " and ".join(files), a.data, e))
        if not a.measured_now and not current[0].startswith("Written by"):
            # A first table needs its measurement's time: only the script that measured knows it.
            sys.exit("gen_bench_tables: block %s of %s has no stamp to keep; write it with --measured-now "
                     "right after measuring (scripts/make_charts.sh, make_stability.sh do)" % (name, a.page))
        if a.measured_now:
            stamp = "Written by `scripts/gen_bench_tables.py` from %s, measured by `%s` on %s UTC, on %s:" % (
                " and ".join("`docs/data/%s`" % f for f in files), script, now_utc(), machine())
        else:
            stamp = current[0]
        if a.check and current[2:] != table:
            sys.exit("gen_bench_tables: block %s of %s differs from the table %s gives; run scripts/"
                     "gen_bench_tables.py --data %s --page %s %s" % (name, a.page, " and ".join(files), a.data,
                                                                   a.page, name))
        new = replace_block(new, name, [stamp, ""] + table)
    if not a.check and new != old:
        open(a.page, "w").write(new)


if __name__ == "__main__":
    main()
