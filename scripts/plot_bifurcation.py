#!/usr/bin/python3
"""Draws the bifurcation diagrams from rotor_rub_bifurcation's CSVs
(scripts/make_bifurcation.sh runs the tool).

usage: plot_bifurcation.py --classes FILE.csv --points FILE.csv.points.csv --out DIR [--stamp TEXT]
                           [--friction F] [--clearance-m C]
Writes DIR/bifurcation.png (the Poincare amplitude against speed at friction
F: constant-speed runs coloured by class; run-up and run-down together),
DIR/bifurcation_map.png (the class over speed x friction, one panel per
direction) and DIR/poincare_sections.png (the section of one constant-speed
run per class, with the clearance circle), and
prints the speed ranges of each class per direction.
"""
import argparse
import csv
import collections
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
import numpy as np  # noqa: E402

# One colour per class (core/response_class.hpp's name table) and per failure.
CLASS_COLOURS = collections.OrderedDict([
    ("no_contact", "#4daf4a"), ("full_rub", "#377eb8"), ("partial_rub", "#ff7f00"),
    ("quasi_periodic", "#984ea3"), ("chaotic", "#e41a1c"), ("aperiodic_rub", "#f781bf"),
    ("backward_whirl", "#000000"),
    ("failed", "#999999"),
])
DIRECTIONS = ("constant", "up", "down")
DIRECTION_LABELS = {"constant": "constant speed, from rest", "up": "run-up (slow ramp)",
                    "down": "run-down (slow ramp)"}


def klass(row):
    return row["class"] if row["status"] == "ok" and row["class"] else "failed"


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def stamp(fig, text):
    fig.text(0.99, 0.005, text, ha="right", va="bottom", fontsize=7, color="#555555")


def legend_handles(present):
    return [Patch(color=CLASS_COLOURS[c], label=c.replace("_", " ")) for c in CLASS_COLOURS if c in present]


def diagram(classes, points, friction, clearance, out, text):
    rows = [r for r in classes if float(r["friction_coefficient"] or "nan") == friction]
    # A constant-speed run has one row: its class colours all its points.
    run_class = {r["run_id"]: klass(r) for r in rows if r["direction"] == "constant"}
    pts = [p for p in points if float(p["friction_coefficient"] or "nan") == friction]
    step = grid_step(classes)
    fig, axes = plt.subplots(2, 1, figsize=(11, 8.5), sharex=True)
    present = set()
    # Constant-speed runs: every Poincare point, coloured by the run's class.
    ax = axes[0]
    const = [p for p in pts if p["direction"] == "constant"]
    for c in CLASS_COLOURS:
        sel = [p for p in const if run_class.get(p["run_id"]) == c]
        if not sel:
            continue
        present.add(c)
        ax.scatter([float(p["speed_rad_per_s"]) for p in sel], [1e3 * float(p["r_rel_m"]) for p in sel], s=3,
                   color=CLASS_COLOURS[c], label=c.replace("_", " "))
    ax.axhline(1e3 * clearance, color="#888888", lw=0.8, ls="--")
    ax.set_ylabel("|r_r - r_s| at the keyphasor [mm]")
    ax.set_title(f"Constant-speed runs (each from rest), friction {friction:g}")
    ax.legend(handles=legend_handles(present), loc="upper right", fontsize=8, ncol=3)
    # Ramps: up and down together, the class as a strip along the bottom.
    ax = axes[1]
    # Direction colours apart from the class colours of the legend.
    for d, colour in (("up", "#17becf"), ("down", "#bcbd22")):
        sel = [p for p in pts if p["direction"] == d]
        if sel:
            ax.scatter([float(p["speed_rad_per_s"]) for p in sel], [1e3 * float(p["r_rel_m"]) for p in sel], s=2,
                       color=colour, alpha=0.6, label=DIRECTION_LABELS[d])
    for k, d in enumerate(("up", "down")):
        for r in rows:
            if r["direction"] != d:
                continue
            w = float(r["speed_rad_per_s"])
            c = klass(r)
            present.add(c)
            ax.add_patch(plt.Rectangle((w - step / 2, -0.35 - 0.25 * k), step, 0.2, color=CLASS_COLOURS[c], lw=0))
    ax.text(0.0, -0.25, "up", fontsize=7, va="center", ha="right", transform=ax.get_yaxis_transform())
    ax.text(0.0, -0.5, "down", fontsize=7, va="center", ha="right", transform=ax.get_yaxis_transform())
    ax.axhline(1e3 * clearance, color="#888888", lw=0.8, ls="--", label="clearance C")
    ax.set_ylim(bottom=-0.65)
    ax.set_yticks([t for t in ax.get_yticks() if t >= 0.0])
    ax.set_xlabel("speed [rad/s]")
    ax.set_ylabel("|r_r - r_s| at the keyphasor [mm]")
    ax.set_title("Slow ramps: run-up and run-down (Poincare points; class strips below)")
    handles = ax.get_legend_handles_labels()[0] + legend_handles(present)
    ax.legend(handles=handles, loc="upper right", fontsize=8, ncol=2)
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    stamp(fig, text)
    fig.savefig(f"{out}/bifurcation.png", dpi=110)
    plt.close(fig)


def grid_step(classes):
    """The spacing of the speed grid (bars and strips are that wide)."""
    speeds = sorted({float(r["speed_rad_per_s"]) for r in classes})
    return min(b - a for a, b in zip(speeds, speeds[1:])) if len(speeds) > 1 else 1.0


def class_map(classes, out, text):
    frictions = sorted({float(r["friction_coefficient"]) for r in classes if r["friction_coefficient"]})
    step = grid_step(classes)
    fig, axes = plt.subplots(len(DIRECTIONS), 1, figsize=(11, 2.0 + 1.6 * len(DIRECTIONS)), sharex=True)
    present = set()
    for ax, d in zip(axes, DIRECTIONS):
        rows = [r for r in classes if r["direction"] == d and r["friction_coefficient"]]
        for r in rows:
            f = float(r["friction_coefficient"])
            w = float(r["speed_rad_per_s"])
            c = klass(r)
            present.add(c)
            ax.add_patch(plt.Rectangle((w - step / 2, frictions.index(f) - 0.4), step, 0.8, color=CLASS_COLOURS[c],
                                       lw=0))
        ax.set_yticks(range(len(frictions)))
        ax.set_yticklabels([f"{f:g}" for f in frictions])
        ax.set_ylim(-0.6, len(frictions) - 0.4)
        ax.set_ylabel("friction f")
        ax.set_title(DIRECTION_LABELS[d], fontsize=10)
    speeds = [float(r["speed_rad_per_s"]) for r in classes]
    axes[-1].set_xlim(min(speeds) - step, max(speeds) + step)
    axes[-1].set_xlabel("speed [rad/s]")
    axes[0].legend(handles=legend_handles(present), loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    stamp(fig, text)
    fig.savefig(f"{out}/bifurcation_map.png", dpi=110)
    plt.close(fig)


def sections(classes, points, clearance, out, text):
    """The Poincare section of one constant-speed run per class: the first
    run (lowest friction, then lowest speed) showing it."""
    rows = [r for r in classes if r["direction"] == "constant" and r["status"] == "ok"]
    rows.sort(key=lambda r: (float(r["friction_coefficient"]), float(r["speed_rad_per_s"])))
    picked = collections.OrderedDict()
    for c in CLASS_COLOURS:
        for r in rows:
            if klass(r) == c:
                picked[c] = r
                break
    if not picked:
        return
    fig, axes = plt.subplots(1, len(picked), figsize=(3.3 * len(picked), 4.0), squeeze=False)
    lim = 1.15e3 * clearance
    circle = np.linspace(0, 2 * np.pi, 200)
    for ax, (c, r) in zip(axes[0], picked.items()):
        sel = [p for p in points if p["run_id"] == r["run_id"]]
        ax.plot(1e3 * clearance * np.cos(circle), 1e3 * clearance * np.sin(circle), color="#888888", lw=0.7,
                ls="--")
        ax.scatter([1e3 * float(p["x_rel_m"]) for p in sel], [1e3 * float(p["y_rel_m"]) for p in sel], s=8,
                   color=CLASS_COLOURS[c])
        ax.set_xlim(-lim, lim)
        ax.set_ylim(-lim, lim)
        ax.set_aspect("equal")
        motion = r["motion"] + (f" {r['period']}" if r["motion"] == "periodic" else "")
        ax.set_title(f"{c.replace('_', ' ')}: {motion}\n{float(r['speed_rad_per_s']):.0f} rad/s, "
                     f"f {float(r['friction_coefficient']):g}, {len(sel)} points", fontsize=9)
        ax.set_xlabel("x_r - x_s [mm]")
    axes[0][0].set_ylabel("y_r - y_s [mm]")
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    stamp(fig, text)
    fig.savefig(f"{out}/poincare_sections.png", dpi=110)
    plt.close(fig)


def ranges(classes):
    """Per friction and direction, the speed ranges of each class."""
    out = []
    groups = collections.defaultdict(list)
    for r in classes:
        groups[(r["friction_coefficient"], r["direction"])].append(r)
    for (f, d), rows in sorted(groups.items()):
        seq = []
        for r in rows:
            c, w = klass(r), float(r["speed_rad_per_s"])
            if seq and seq[-1][0] == c:
                seq[-1][2] = w
            else:
                seq.append([c, w, w])
        out.append(f"f {f} {d:8s} " + " | ".join(f"{c} {a:g}-{b:g}" for c, a, b in seq))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--classes", required=True)
    ap.add_argument("--points", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--stamp", default="", help="a note in the corner (what made the data, when)")
    ap.add_argument("--friction", type=float, default=0.1, help="the friction of the diagram and sections")
    ap.add_argument("--clearance-m", type=float, default=2e-3)
    a = ap.parse_args()
    classes, points = read(a.classes), read(a.points)
    if not classes:
        raise SystemExit(f"plot_bifurcation: '{a.classes}' has no rows")
    # The charts take friction as the second parameter: a grid that varies
    # another key too would be drawn as if it did not.
    others = {";".join(kv for kv in r["overrides"].split(";") if kv and not kv.startswith("friction_coefficient="))
              for r in classes}
    if len(others) > 1:
        raise SystemExit("plot_bifurcation: the grid varies more than friction_coefficient (%s); the charts draw "
                         "friction as the second parameter: plot one setting of the others at a time"
                         % " | ".join(sorted(o or "-" for o in others)))
    frictions = sorted({float(r["friction_coefficient"]) for r in classes if r["friction_coefficient"]})
    if a.friction not in frictions:
        raise SystemExit(f"plot_bifurcation: no rows at --friction {a.friction:g}; the CSV has "
                         + ", ".join(f"{f:g}" for f in frictions))
    os.makedirs(a.out, exist_ok=True)
    diagram(classes, points, a.friction, a.clearance_m, a.out, a.stamp)
    class_map(classes, a.out, a.stamp)
    sections(classes, points, a.clearance_m, a.out, a.stamp)
    for line in ranges(classes):
        print(line)


if __name__ == "__main__":
    main()
