#!/usr/bin/python3
"""Draws the synchronous full rub's branches (rotor_rub_stability --csv) over
what the brute-force runs found (rotor_rub_bifurcation's classes CSV): the
normal force against speed, each branch solid where stable and dashed where
not, and the mean normal force of every run the bifurcation tool classed as
full rub at that friction (constant speed, run-up, run-down). A user sees
the sweep land on the stable branch, and the unstable branches no sweep
can show. Prints, per direction, the speeds where the runs were in full rub
against those where the upper branch is stable. With --continuation, the
branch traced through its folds by continuation (rotor_rub_stability
--branch-csv) is drawn over the grid's, in red, and the speeds where it
turns back (its folds) are marked and printed.

usage: plot_full_rub.py --branches STABILITY.csv --out FILE.png [--classes BIFURCATION.csv --friction F]
                        [--continuation BRANCH.csv] [--title TEXT]
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MARKERS = {"constant": ("o", "#377eb8"), "up": ("^", "#17becf"), "down": ("v", "#bcbd22")}


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def runs_of(rows, key):
    """Contiguous runs of rows sharing key(row), in order."""
    out = []
    for r in rows:
        if out and key(out[-1][-1]) == key(r):
            out[-1].append(r)
        else:
            out.append([r])
    return out


def turning_points(speeds):
    """The indices where a traced speed turns back (a fold between neighbours)."""
    return [i for i in range(1, len(speeds) - 1) if (speeds[i] - speeds[i - 1]) * (speeds[i + 1] - speeds[i]) < 0.0]


def draw_continuation(ax, trace):
    """The traced branch: solid where stable, dashed where not, each piece
    joined to the next at their shared point; its folds marked."""
    pieces = runs_of(trace, lambda r: r["stable"])
    for k, part in enumerate(pieces):
        pts = part + ([pieces[k + 1][0]] if k + 1 < len(pieces) else [])
        stable = part[0]["stable"] == "1"
        ax.plot([float(r["speed_rad_per_s"]) for r in pts], [float(r["normal_force_N"]) for r in pts],
                color="#e41a1c", ls="-" if stable else "--", lw=1.0, zorder=4,
                label="continuation, %s" % ("stable" if stable else "unstable"))
    speeds = [float(r["speed_rad_per_s"]) for r in trace]
    for i in turning_points(speeds):
        ax.scatter([speeds[i]], [float(trace[i]["normal_force_N"])], marker="x", s=40, color="#e41a1c", zorder=5,
                   label="continuation's fold")
        print("plot_full_rub: the continuation turns back at %.6g rad/s" % speeds[i])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--branches", required=True, help="rotor_rub_stability --csv output")
    ap.add_argument("--out", required=True, help="the PNG to write")
    ap.add_argument("--classes", help="rotor_rub_bifurcation's classes CSV (the runs' class and mean normal force)")
    ap.add_argument("--friction", type=float, help="the friction coefficient of the runs to draw (with --classes)")
    ap.add_argument("--continuation", help="rotor_rub_stability --branch-csv output: the branch traced through its folds")
    ap.add_argument("--title", default="synchronous full rub: branches and runs")
    a = ap.parse_args(argv)
    if a.classes and a.friction is None:
        ap.error("--classes needs --friction")
    try:
        branches = read(a.branches)
        classes = read(a.classes) if a.classes else []
        trace = read(a.continuation) if a.continuation else []
    except (OSError, csv.Error) as e:
        print("plot_full_rub.py: cannot read: %s" % e, file=sys.stderr)
        return 2
    if not branches:
        print("plot_full_rub.py: %s holds no branch (no full rub in its speed range)" % a.branches, file=sys.stderr)
        return 2
    fig, ax = plt.subplots(figsize=(10, 5))
    stable_spans = []  # the upper branch's stable stretches on the grid
    for b in sorted({r["branch"] for r in branches}):
        rows = sorted((r for r in branches if r["branch"] == b), key=lambda r: float(r["speed_rad_per_s"]))
        # A gap in speed (no branch between: past a fold) breaks the line too.
        grid = sorted({float(r["speed_rad_per_s"]) for r in branches})
        step = min((y - x for x, y in zip(grid, grid[1:])), default=0.0)
        # A new part where the verdict changes or the branch has a gap (a fold).
        last = [None]

        def part_key(r):
            w = float(r["speed_rad_per_s"])
            gap = last[0] is not None and w - last[0] > 1.5 * step
            last[0] = w
            part_key.n += gap
            return (r["stable"], part_key.n)
        part_key.n = 0
        for part in runs_of(rows, part_key):
            w = [float(r["speed_rad_per_s"]) for r in part]
            n = [float(r["normal_force_N"]) for r in part]
            stable = part[0]["stable"] == "1"
            ax.plot(w, n, color="k" if b == "0" else "#666666", ls="-" if stable else "--", lw=1.4 if stable else 1.0,
                    label="branch %s, %s" % (b, "stable" if stable else "unstable"))
            if b == "0" and stable:
                stable_spans.append((w[0], w[-1]))
    if trace:
        draw_continuation(ax, trace)
    runs = [r for r in classes if r["status"] == "ok" and r["class"] == "full_rub" and r["friction_coefficient"]
            and abs(float(r["friction_coefficient"]) - a.friction) < 1e-12]
    for d, (marker, colour) in MARKERS.items():
        sel = [r for r in runs if r["direction"] == d]
        if sel:
            ax.scatter([float(r["speed_rad_per_s"]) for r in sel], [float(r["mean_normal_force_N"]) for r in sel],
                       marker=marker, s=14, color=colour, zorder=3, label="runs in full rub: %s" % d)
            ws = sorted(float(r["speed_rad_per_s"]) for r in sel)
            print("plot_full_rub: %s runs in full rub from %.4g to %.4g rad/s" % (d, ws[0], ws[-1]))
    if stable_spans:
        print("plot_full_rub: the upper branch is stable at %s rad/s (on the grid)"
              % ", ".join("%.4g-%.4g" % span for span in stable_spans))
    ax.set_xlabel("speed [rad/s]")
    ax.set_yscale("log")  # from a fraction of a newton at the onset to hundreds
    ax.set_ylabel("normal force N [N]")
    ax.set_title(a.title)
    handles, labels = ax.get_legend_handles_labels()
    seen = {}
    for h, l in zip(handles, labels):
        seen.setdefault(l, h)
    ax.legend(seen.values(), seen.keys(), fontsize=8, loc="upper left")
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    plt.close(fig)
    print("plot_full_rub: wrote %s" % a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
