#!/usr/bin/python3
"""Draws periodic orbits' branches (rotor_rub_orbits --continue --csv) over
the brute-force bifurcation diagram (rotor_rub_bifurcation's Poincare points
CSV): the Poincare radius |rotor - stator| at the keyphasor against speed,
each branch solid where stable and dashed where not (a period-n orbit has n
points per speed), its bifurcations marked, and every run's Poincare points
as dots. A user sees the runs land on the stable parts and the unstable
parts that no sweep shows. Prints, per bifurcation, its kind and speed.

usage: plot_orbits.py --orbits ORBITS.csv --out FILE.png [--points BIFURCATION.csv.points.csv] [--title TEXT]
                      [--zoom LO HI] [--xlabel TEXT]
The abscissa is the branches' parameter (rotor_rub_orbits --parameter: the speed unless a key was
traced; then --xlabel names it, and --points, runs over speed, does not apply).
With --zoom, a second panel shows the speeds LO..HI (a cascade of doublings).
"""
import argparse
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

BIFURCATION_MARKERS = {"fold": ("x", "#e41a1c"), "period_doubling": ("D", "#984ea3"),
                       "neimark_sacker": ("s", "#ff7f00")}
BRANCH_COLOURS = ["#000000", "#377eb8", "#4daf4a", "#a65628", "#f781bf"]


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def curves(rows):
    """Per (branch, keyphasor): the orbits' points in the CSV's order (along
    the branch), split where the verdict changes; a bifurcation's row (no
    verdict) ends one part and starts the next."""
    out = {}
    for r in rows:
        out.setdefault((r["branch"], r["keyphasor"]), []).append(r)
    parts = []
    for key, pts in out.items():
        current = []
        for r in pts:
            if current and r["stable"] and current[-1]["stable"] and r["stable"] != current[-1]["stable"]:
                parts.append((key, current + [r]))  # no bifurcation row between: meet at the next point
                current = [r]
            elif not r["stable"] and current:
                parts.append((key, current + [r]))
                current = [r]
            else:
                current.append(r)
        if len(current) > 1 or (current and current[0]["stable"]):
            parts.append((key, current))
    return parts


def verdict(part):
    """A part's verdict: its first row's that has one."""
    return next((r["stable"] for r in part if r["stable"]), "1")


def ordinate(angle):
    """The plotted value of a row (an orbit's or a run's point): the radius
    |rotor - stator| [mm], or with angle its direction [deg] (an orbit on the
    bore throughout has the radius C at every point)."""
    def of(row):
        x, y, r = (float(row[k]) if k in row else float(row[k.replace("_m", "_rel_m").replace("radius", "r")])
                   for k in ("x_m", "y_m", "radius_m"))
        return math.degrees(math.atan2(y, x)) if angle else 1e3 * r
    return of


def draw(ax, rows, points, legend, report, xlabel, unit, value):
    if points:
        ax.scatter([float(p["speed_rad_per_s"]) for p in points], [value(p) for p in points], s=3,
                   color="#999999", zorder=1, label="runs' Poincare points (constant speed, settled)")
    labelled = set()
    for (branch, _), part in curves(rows):
        stable = verdict(part) == "1"
        period = part[0]["periods"]
        colour = BRANCH_COLOURS[int(branch) % len(BRANCH_COLOURS)]
        label = "period %s, %s" % (period, "stable" if stable else "unstable")
        ax.plot([float(r["parameter"]) for r in part], [value(r) for r in part], color=colour,
                ls="-" if stable else "--", lw=1.4 if stable else 1.0, zorder=2,
                label=None if (label, colour) in labelled else label)
        labelled.add((label, colour))
    for kind, (marker, colour) in BIFURCATION_MARKERS.items():
        sel = [r for r in rows if r["bifurcation"] == kind]
        if not sel:
            continue
        ax.scatter([float(r["parameter"]) for r in sel], [value(r) for r in sel],
                   marker=marker, s=36, color=colour, zorder=4, label=kind.replace("_", " "))
        if report:
            for w in sorted({float(r["parameter"]) for r in sel}):
                print("plot_orbits: %s at %.6f %s" % (kind.replace("_", " "), w, unit))
    ax.set_xlabel(xlabel)
    ax.set_ylabel("direction of rotor - stator at the keyphasor [deg]" if value.angle else
                  "Poincare radius |rotor - stator| at the keyphasor [mm]")
    if legend:
        ax.legend(fontsize=7, loc="best")
    ax.grid(alpha=0.3)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--orbits", required=True, help="rotor_rub_orbits --csv output")
    ap.add_argument("--out", required=True, help="the PNG to write")
    ap.add_argument("--points", help="rotor_rub_bifurcation's OUT.csv.points.csv (the runs' Poincare points)")
    ap.add_argument("--title", default="periodic orbits: branches and runs")
    ap.add_argument("--zoom", nargs=2, type=float, metavar=("LO", "HI"), help="a second panel over these values")
    ap.add_argument("--xlabel", help="the parameter's name with its unit (default: speed [rad/s])")
    ap.add_argument("--angle", action="store_true",
                    help="plot the direction of rotor - stator at the keyphasor, not its radius (orbits on the bore)")
    a = ap.parse_args(argv)
    try:
        rows = read(a.orbits)
        points = read(a.points) if a.points else []
    except (OSError, csv.Error) as e:
        print("plot_orbits.py: cannot read: %s" % e, file=sys.stderr)
        return 2
    if not rows:
        print("plot_orbits.py: %s holds no orbit" % a.orbits, file=sys.stderr)
        return 2
    if a.zoom:
        fig, axes = plt.subplots(1, 2, figsize=(14, 5), gridspec_kw={"width_ratios": [3, 2]})
    else:
        fig, axes = plt.subplots(figsize=(10, 5))
        axes = [axes]
    value = ordinate(a.angle)
    value.angle = a.angle
    for i, ax in enumerate(axes):
        draw(ax, rows, points, legend=i == 0, report=i == 0, xlabel=a.xlabel or "speed [rad/s]",
             unit="rad/s" if not a.xlabel else "", value=value)
        ax.set_title(a.title if i == 0 else "%g to %g" % tuple(a.zoom))
    if a.zoom:
        lo, hi = a.zoom
        axes[1].set_xlim(lo, hi)
        inside = [value(r) for r in rows if lo <= float(r["parameter"]) <= hi]
        inside += [value(p) for p in points if lo <= float(p["speed_rad_per_s"]) <= hi]
        if inside:
            pad = 0.05 * (max(inside) - min(inside) or 1.0)
            axes[1].set_ylim(min(inside) - pad, max(inside) + pad)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print("plot_orbits: wrote %s" % a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
