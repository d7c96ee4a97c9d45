#!/usr/bin/python3
"""Draws the speed-against-accuracy charts from the sweep CSVs and the runner's
traces, without running anything (scripts/make_charts.sh runs the sweeps).

usage: plot_charts.py --data DIR --traces DIR --out DIR --stamp TEXT

  DIR/work_precision.csv, parameter_study.csv  (rotor_rub_sweep)
  DIR/bench.csv, when there (rotor_rub_bench --csv): CVODE's curves on the work-precision chart
  TRACES/<name>.csv and <name>.json for reference, switching, iteration, penalty (rotor_rub_run)
Writes work_precision.png, contact_force.png, trajectories.png and parameter_study.png
into OUT (the tables from the same CSVs: scripts/gen_bench_tables.py). Every chart
carries the stamp (scene, cores, date, command).
"""
import argparse
import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# The sweeps' CSVs read as the tables of docs/benchmarks.md read them; COMPLETED:
# the runs that reached the end, drawn on the curves.
from gen_bench_tables import COMPLETED, fnum, read_csv  # noqa: E402

METHOD_COLOURS = {"switching": "tab:blue", "iteration": "tab:green", "penalty": "tab:red", "reference": "black",
                  "cvode": "tab:purple"}
BAD_WINDOW_COLOUR = "magenta"  # not a method's colour
FAIL_MARKERS = {"stalled": "X", "diverged": "D", "not_converged": "s", "timed_out": "v", "invariant_violated": "^",
                "invalid": "P",
                "no_reference": "*"}
WINDOW_S = 1e-3  # the impulse window of the force comparison (rotor_rub_sweep --window-ms 1)


def stamp(fig, text):
    fig.text(0.01, 0.005, text, fontsize=6.5, color="0.35", ha="left", va="bottom", wrap=True)


def curve_key(r):
    label = "%s / %s" % (r["method"], r["integrator"])
    if r["method"] == "penalty":
        label += ", k_c %.0e N/m" % fnum(r, "contact_stiffness_N_per_m")
    return label


# ---- work-precision -------------------------------------------------------
def work_precision(rows, out, text, bench_rows=()):
    fig, axes = plt.subplots(1, 2, figsize=(16, 5.8))
    curves = {}
    for r in rows:
        curves.setdefault(curve_key(r), []).append(r)
    # The same model on SUNDIALS CVODE, from rotor_rub_bench --csv (timed
    # without output; ours with samples at the scene's 1 kHz).
    for r in bench_rows:
        if r["method"] == "cvode":
            curves.setdefault("CVODE %s (rotor_rub_bench, no output, "
                              "one run at a time)" % r["integrator"], []).append(r)
    styles = ["-", "--", ":", "-."]
    for i, (label, rs) in enumerate(sorted(curves.items())):
        rs.sort(key=lambda r: -fnum(r, "rtol"))
        colour = METHOD_COLOURS.get(rs[0]["method"], "grey")
        ls = styles[i % len(styles)] if rs[0]["method"] in ("penalty", "cvode") else (
            "--" if rs[0]["integrator"] == "dop853" else ":" if rs[0]["integrator"] == "rosenbrock4" else "-")
        marker = {"dopri5": "o", "adams": "s", "bdf": "D", "rkf78": "^", "dop853": "v",
                  "rosenbrock4": "P"}.get(rs[0]["integrator"], "^")
        for ax, xkey in zip(axes, ("wall_time_s", "rhs_evals")):
            ok = [r for r in rs if r["status"] in COMPLETED]
            ax.plot([fnum(r, xkey) for r in ok], [fnum(r, "max_rotor_err_m") for r in ok], ls, marker=marker,
                    color=colour, label=label, alpha=0.85, markersize=4)
            # Failed runs: drawn where they stopped (their cost, their error
            # over the samples they delivered), marked with their class.
            failed = [r for r in rs if r["status"] not in COMPLETED]
            for r in failed:
                y = fnum(r, "max_rotor_err_m")
                x = fnum(r, xkey)
                if not (y > 0) or not math.isfinite(y):
                    y = 1e-2
                ax.plot([x], [y], FAIL_MARKERS.get(r["status"], "X"), color=colour, markersize=10,
                        markeredgecolor="k")
            # One label per curve and class, at its loosest failed run (the
            # marker shapes carry the rest), so labels do not pile up.
            for status in sorted({r["status"] for r in failed}):
                fs = [r for r in failed if r["status"] == status]
                r = max(fs, key=lambda q: fnum(q, "rtol"))
                y = fnum(r, "max_rotor_err_m")
                y = y if (y > 0 and math.isfinite(y)) else 1e-2
                ax.annotate("%s, rtol <= %s" % (status, r["rtol"]), (fnum(r, xkey), y), fontsize=6.5,
                            textcoords="offset points", xytext=(6, -10))
    for ax, xl in zip(axes, ("wall time of the integration [s] (median of repeats)", "right-hand-side evaluations")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xl)
        ax.set_ylabel("max |r_r - r_r,ref| over the run [m]")
        ax.grid(True, which="both", alpha=0.3)
        ax.axhline(1e-6, color="0.5", lw=0.8, ls="--")
    axes[0].set_title("error against cost, rtol 1e-2 .. 1e-10 (atol = 1e-3 rtol)")
    axes[1].set_title("the same against derivative evaluations")
    handles, labels = axes[1].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=7, loc="center right", ncol=1)  # beside the data, not over it
    fig.tight_layout(rect=(0, 0.04, 0.8, 1))
    stamp(fig, text)
    fig.savefig(os.path.join(out, "work_precision.png"), dpi=110)
    plt.close(fig)


# ---- traces ------------------------------------------------------------------
def load_trace(traces, name):
    data = np.genfromtxt(os.path.join(traces, name + ".csv"), delimiter=",", names=True)
    with open(os.path.join(traces, name + ".json")) as f:
        summary = json.load(f)
    return data, summary


def windowed_force(data, events, t_end):
    """Impulse per 1 ms window / 1 ms: trapezoid on F_n plus impact impulses."""
    t, f = data["t"], data["normal_force"]
    n = int(math.ceil(t_end / WINDOW_S)) + 1
    imp = np.zeros(n)
    seg = 0.5 * (f[1:] + f[:-1]) * np.diff(t)
    k = np.floor(t[:-1] / WINDOW_S + 1e-9).astype(int)
    np.add.at(imp, k, seg)
    for e in events:
        imp[int(math.floor(e["t"] / WINDOW_S))] += e.get("impulse_N_s") or 0.0
    return (np.arange(n) + 0.5) * WINDOW_S, imp / WINDOW_S


def contact_intervals(data):
    c = data["in_contact"] > 0.5
    t = data["t"]
    edges = np.flatnonzero(np.diff(c.astype(int)))
    starts = [t[0]] if c[0] else []
    ends = []
    for i in edges:
        (starts if not c[i] else ends).append(t[i + 1])
    if c[-1]:
        ends.append(t[-1])
    return list(zip(starts, ends))


def contact_force(traces, names, out, text):
    ref, ref_sum = load_trace(traces, "reference")
    t_end = ref["t"][-1]
    wt, wref = windowed_force(ref, ref_sum["events"], t_end)
    peak = np.max(wref)
    ref_contact = np.zeros_like(wref, dtype=bool)
    for a, b in contact_intervals(ref):
        ref_contact |= (wt >= a - WINDOW_S) & (wt <= b + WINDOW_S)
    fig, axes = plt.subplots(len(names) + 1, 1, figsize=(12, 2.6 * (len(names) + 1)), sharex=True)
    axes[0].plot(ref["t"], ref["normal_force"], color="black", lw=0.6, label="reference raw F_n")
    axes[0].step(wt, wref, where="mid", color="tab:orange", lw=1.0, label="reference, 1 ms windows")
    axes[0].set_ylabel("F_n [N]")
    axes[0].legend(fontsize=7, loc="upper right")
    axes[0].set_title("normal force, raw and averaged over 1 ms windows (impact impulses included)")
    lines = []
    for ax, name in zip(axes[1:], names):
        d, s = load_trace(traces, name)
        ax.plot(d["t"], d["normal_force"], color=METHOD_COLOURS[name], lw=0.5, alpha=0.6, label=name + " raw F_n")
        _, w = windowed_force(d, s["events"], t_end)
        w = w[: len(wref)]
        ax.step(wt[: len(w)], w, where="mid", color="k", lw=0.9, label=name + ", 1 ms windows")
        ax.step(wt, wref, where="mid", color="tab:orange", lw=0.8, ls="--", label="reference, 1 ms windows")
        err = np.abs(w - wref[: len(w)]) / peak
        mask = ref_contact[: len(w)]
        bad = mask & (err > 0.05)
        worst = int(np.argmax(np.where(mask, err, 0)))
        lines.append("%s (%s, rtol %s): windowed force within 5 %% of the reference's peak (%.1f N) in %.1f %% of "
                     "%d contact windows; worst %.0f %% at t = %.3f s"
                     % (name, s["integrator"], s["rtol"], peak, 100.0 * (1 - bad.sum() / max(mask.sum(), 1)),
                        mask.sum(), 100 * err[worst], wt[worst]))
        for i in np.flatnonzero(bad):
            ax.axvspan(wt[i] - WINDOW_S / 2, wt[i] + WINDOW_S / 2, color=BAD_WINDOW_COLOUR, alpha=0.35, lw=0)
        ylim = max(1.3 * peak, 1.0)  # the windowed forces fill the axis; raw impact spikes are clipped
        ax.set_ylim(-0.05 * ylim, ylim)
        ax.set_ylabel("F_n [N]")
        ax.legend(fontsize=7, loc="upper right")
    axes[-1].set_xlabel("t [s]   (magenta: windows off by more than 5 % of the reference's peak; raw F_n clipped at "
                        "1.3x the peak)")
    contact = [(a, b) for a, b in contact_intervals(ref)]
    if contact:
        axes[-1].set_xlim(max(0.0, contact[0][0] - 0.05), min(t_end, contact[-1][1] + 0.05))
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    stamp(fig, text)
    fig.savefig(os.path.join(out, "contact_force.png"), dpi=110)
    plt.close(fig)
    return lines


def trajectories(traces, names, out, text, clearance_m):
    all_names = ["reference"] + names
    fig = plt.figure(figsize=(13, 2.4 * len(all_names)))
    gs = fig.add_gridspec(len(all_names), 2, width_ratios=(3, 1))
    for i, name in enumerate(all_names):
        d, s = load_trace(traces, name)
        ax = fig.add_subplot(gs[i, 0])
        ax.plot(d["t"], d["x_r"] * 1e3, color=METHOD_COLOURS[name], lw=0.4)
        for a, b in contact_intervals(d):
            ax.axvspan(a, b, color="0.6", alpha=0.35, lw=0)
        ax.set_ylabel("x_r [mm]")
        ax.set_title("%s (%s, rtol %s): rotor x, contact shaded" % (name, s["integrator"], s["rtol"]), fontsize=9)
        if i == len(all_names) - 1:
            ax.set_xlabel("t [s]")
        ax2 = fig.add_subplot(gs[i, 1])
        # The orbit relative to the stator (what probes on the casing see):
        # the rotor touches when |r_r - r_s| = C, the circle. The absolute
        # orbit reaches 4.5 mm on this scene because the stator moves with it.
        ax2.plot((d["x_r"] - d["x_s"]) * 1e3, (d["y_r"] - d["y_s"]) * 1e3, color=METHOD_COLOURS[name], lw=0.3)
        th = np.linspace(0, 2 * np.pi, 400)
        ax2.plot(clearance_m * 1e3 * np.cos(th), clearance_m * 1e3 * np.sin(th), "k--", lw=0.8)
        ax2.set_aspect("equal")
        ax2.set_xlabel("x_r - x_s [mm]")
        ax2.set_ylabel("y_r - y_s [mm]")
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    stamp(fig, text)
    fig.savefig(os.path.join(out, "trajectories.png"), dpi=100)
    plt.close(fig)


def parameter_study(rows, out, text):
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.6))
    by_e = {}
    for r in rows:
        by_e.setdefault(fnum(r, "eccentricity_m"), []).append(r)
    for e, rs in sorted(by_e.items()):
        rs.sort(key=lambda r: fnum(r, "friction_coefficient"))
        f = [fnum(r, "friction_coefficient") for r in rs]
        for ax, key, scale in zip(axes, ("max_orbit_m", "contact_time_s", "peak_normal_force_N"), (1e3, 1, 1)):
            ok = [r["status"] in COMPLETED for r in rs]
            y = [fnum(r, key) * scale for r in rs]
            ax.plot([x for x, o in zip(f, ok) if o], [v for v, o in zip(y, ok) if o], "o-",
                    label="e = %.1f mm" % (e * 1e3))
            for x, v, r in zip(f, y, rs):
                if r["status"] not in COMPLETED:
                    ax.plot([x], [v], FAIL_MARKERS.get(r["status"], "X"), color="k", markersize=9)
    for ax, yl in zip(axes, ("max orbit |r_r| [mm]", "time in contact [s]", "peak normal force [N]")):
        ax.set_xlabel("friction coefficient f")
        ax.set_ylabel(yl)
        ax.grid(True, alpha=0.3)
    axes[0].legend(fontsize=8)
    axes[1].set_title("paper run-up, switching rtol 1e-8: friction and unbalance")
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    stamp(fig, text)
    fig.savefig(os.path.join(out, "parameter_study.png"), dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--data", required=True)
    ap.add_argument("--traces", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--stamp", required=True)
    ap.add_argument("--clearance", type=float, default=2e-3)
    ap.add_argument("--work-precision-only", action="store_true",
                    help="only the work-precision chart (the one the bench's CSV feeds)")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    wp = read_csv(os.path.join(a.data, "work_precision.csv"))
    bench_csv = os.path.join(a.data, "bench.csv")  # rotor_rub_bench --csv, when there
    work_precision(wp, a.out, a.stamp, read_csv(bench_csv) if os.path.exists(bench_csv) else ())
    if a.work_precision_only:
        print("chart written to", a.out)
        return
    names = ["switching", "iteration", "penalty"]
    for line in contact_force(a.traces, names, a.out, a.stamp):
        print(line)
    trajectories(a.traces, names, a.out, a.stamp, a.clearance)
    parameter_study(read_csv(os.path.join(a.data, "parameter_study.csv")), a.out, a.stamp)
    print("charts written to", a.out)


if __name__ == "__main__":
    main()
