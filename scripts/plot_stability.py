#!/usr/bin/python3
"""Draws the stability maps (issue 5) from the campaign's sweep CSVs: every run
a cell coloured by its class. scripts/make_stability.sh runs the sweeps.

usage: plot_stability.py --data DIR --out DIR --stamp TEXT [--scene FILE]
Writes stability_penalty.png, stability_switching.png, stability_iteration.png,
stability_stick_slip.png and prints each method's measured safe region.
"""
import argparse
import csv
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402
import numpy as np  # noqa: E402

CLASS_COLOURS = {
    "ok": "#4daf4a", "inaccurate": "#ffd92f", "stalled": "#ff7f00", "diverged": "#e41a1c",
    "not_converged": "#984ea3", "timed_out": "#999999", "invariant_violated": "#000000", "no_reference": "#a6cee3",
    "invalid": "white",
}
COMPLETED = ("ok", "inaccurate", "no_reference")
# Axes that are not scene keys get a plain name (the sweep's pseudo-key
# constant_speed_rad_per_s sets initial and target speed alike).
AXIS_LABELS = {"constant_speed_rad_per_s": "constant speed [rad/s] (initial = target speed)"}


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def value(row, key):
    """A setting: its own column, or from other_settings ("k=v;k=v")."""
    if key in row and row[key] != "":
        return float(row[key])
    for kv in row.get("other_settings", "").split(";"):
        k, _, v = kv.partition("=")
        if k == key:
            return float(v)
    if key == "constant_speed_rad_per_s":
        return value(row, "initial_speed_rad_per_s")
    return math.nan


def stamp(fig, text):
    fig.text(0.01, 0.005, text, fontsize=6.5, color="0.35", ha="left", va="bottom")


def class_map(ax, rows, xkey, ykey, title, logx=False, logy=False):
    xs = sorted({value(r, xkey) for r in rows})
    ys = sorted({value(r, ykey) for r in rows})
    for r in rows:
        i, j = xs.index(value(r, xkey)), ys.index(value(r, ykey))
        ax.add_patch(plt.Rectangle((i - 0.5, j - 0.5), 1, 1, color=CLASS_COLOURS.get(r["status"], "black"),
                                   ec="white", lw=0.8))
    ax.set_xlim(-0.5, len(xs) - 0.5)
    ax.set_ylim(-0.5, len(ys) - 0.5)
    ax.set_xticks(range(len(xs)))
    ax.set_xticklabels(["%.3g" % x for x in xs], rotation=45, fontsize=7)
    ax.set_yticks(range(len(ys)))
    ax.set_yticklabels(["%.3g" % y for y in ys], fontsize=7)
    ax.set_xlabel(AXIS_LABELS.get(xkey, xkey))
    ax.set_ylabel(AXIS_LABELS.get(ykey, ykey))
    ax.set_title(title, fontsize=9)
    return xs, ys


def legend(fig, statuses):
    handles = [Patch(color=CLASS_COLOURS[s], label=s) for s in CLASS_COLOURS if s in statuses]
    fig.legend(handles=handles, loc="upper right", ncol=len(handles), fontsize=8)


def scene_masses(scene):
    vals = {"rotor_mass_kg": 0.418, "stator_mass_kg": 0.86}
    if scene and os.path.exists(scene):
        for line in open(scene):
            k, _, v = line.split("#")[0].partition(":")
            if k.strip() in vals and v.strip():
                vals[k.strip()] = float(v)
    return vals["rotor_mass_kg"], vals["stator_mass_kg"]


def rk4_radius(angle):
    """Largest r with |R(r e^{i angle})| <= 1 for RK4 (bisection from the origin)."""
    R = lambda z: abs(1 + z + z ** 2 / 2 + z ** 3 / 6 + z ** 4 / 24)  # noqa: E731
    lo, hi = 1e-6, 4.0
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        (lo, hi) = (mid, hi) if R(mid * complex(math.cos(angle), math.sin(angle))) <= 1 else (lo, mid)
    return lo


def penalty_damping_ratio(restitution, contact_stiffness):
    """contact_law.hpp's inversion of the clamped spring-dashpot's rebound
    ratio, by bisection, with its floor: 0.01 up to k_c 1e9, then
    0.01 sqrt(1e9 / k_c)."""
    e = max(restitution, 0.01 * math.sqrt(min(1.0, 1e9 / contact_stiffness)))

    def rebound(z):
        if z < 1:
            q = z / math.sqrt(1 - z * z)
            return math.exp(-q * (math.pi - 2 * math.atan(q)))
        if z == 1:
            return math.exp(-2)
        p = z / math.sqrt(z * z - 1)
        return math.exp(-p * math.log((p + 1) / (p - 1)))
    lo, hi = 0.0, 1e4
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        (lo, hi) = (mid, hi) if rebound(mid) > e else (lo, mid)
    return lo


def penalty(data, out, text, scene):
    rk4 = read_csv(os.path.join(data, "stability_penalty_rk4.csv"))
    adaptive = read_csv(os.path.join(data, "stability_penalty_adaptive.csv"))
    violent = [r for r in read_csv(os.path.join(data, "stability_violent.csv")) if r["method"] == "penalty"]
    fig, axes = plt.subplots(1, 3, figsize=(17, 5.6), gridspec_kw={"width_ratios": (1.3, 1, 0.8)})
    xs, ys = class_map(axes[0], rk4, "contact_stiffness_N_per_m", "fixed_step_s",
                       "fixed-step RK4: class per (k_c, h); line: theory h_max = 2.785 / |lambda_max|; white: refused")
    # Theory: e = 0 makes the penalty damper overdamped (zeta = 4.81 up to
    # k_c 1e9, more above: the restitution floor of contact_law.hpp): real eigenvalues
    # -omega_c (zeta +- sqrt(zeta^2 - 1)), omega_c = sqrt(k_c / m_eff); RK4 is
    # stable on [-2.785, 0] of the real axis.
    mr, ms = scene_masses(scene)
    m_eff = 1.0 / (1.0 / mr + 1.0 / ms)
    r = rk4_radius(math.pi)
    kc = np.logspace(math.log10(xs[0]), math.log10(xs[-1]), 200)
    def fast(k):  # |lambda_max| / omega_c
        z = penalty_damping_ratio(0.0, k)
        return z + math.sqrt(z * z - 1.0)
    h_theory = np.array([r / (fast(k) * math.sqrt(k / m_eff)) for k in kc])
    # Map onto the cell grid (log interpolation between cell centres).
    lx = np.interp(np.log10(kc), np.log10(xs), np.arange(len(xs)))
    ly = np.interp(np.log10(h_theory), np.log10(ys), np.arange(len(ys)), left=-0.5, right=len(ys) - 0.5)
    axes[0].plot(lx, ly, "k-", lw=2)
    measured = []
    for k in xs:
        cells = sorted((value(q, "fixed_step_s"), q["status"]) for q in rk4 if value(q, "contact_stiffness_N_per_m") == k)
        stable = None
        for h, st in cells:
            if st not in COMPLETED:
                break
            stable = h
        first_bad = next(("%s at %.3g" % (st, h) for h, st in cells if st not in COMPLETED), None)
        measured.append((k, stable, first_bad, r / (fast(k) * math.sqrt(k / m_eff))))
    # Adaptive: cost against k_c.
    for integ, mk in (("dopri5", "o"), ("rosenbrock4", "^")):
        rows = sorted((q for q in adaptive if q["integrator"] == integ), key=lambda q: value(q, "contact_stiffness_N_per_m"))
        k = [value(q, "contact_stiffness_N_per_m") for q in rows]
        w = [value(q, "wall_time_s") for q in rows]
        axes[1].plot(k, w, mk + "-", label=integ + " wall [s]")
        for q, kk, ww in zip(rows, k, w):
            if q["status"] not in ("ok", "inaccurate"):
                axes[1].annotate(q["status"], (kk, ww), fontsize=7, color="red")
        axes[1].plot(k, [value(q, "steps") * 1e-6 for q in rows], mk + ":", label=integ + " steps / 1e6")
    axes[1].set_xscale("log")
    axes[1].set_yscale("log")
    axes[1].set_xlabel("contact_stiffness_N_per_m")
    axes[1].set_title("adaptive, rtol 1e-6: cost against k_c", fontsize=9)
    axes[1].grid(True, which="both", alpha=0.3)
    axes[1].legend(fontsize=7)
    class_map(axes[2], violent, "constant_speed_rad_per_s", "friction_coefficient",
              "dopri5 rtol 1e-6, constant speed from rest, 1 s")
    legend(fig, {q["status"] for q in rk4 + adaptive + violent})
    fig.suptitle("penalty method (I): where it fails", x=0.3)
    fig.tight_layout(rect=(0, 0.03, 1, 0.93))
    stamp(fig, text)
    fig.savefig(os.path.join(out, "stability_penalty.png"), dpi=100)
    plt.close(fig)
    return measured


def method_figure(data, out, text, method, title, panels):
    """One figure per rigid method: a class map per (csv name, x key, y key,
    panel title), then the violent-physics map of the method."""
    fig, axes = plt.subplots(1, len(panels) + 1, figsize=(17, 5.4))
    tables = []
    for ax, (name, xkey, ykey, panel_title) in zip(axes, panels):
        rows = read_csv(os.path.join(data, "stability_%s.csv" % name))
        class_map(ax, rows, xkey, ykey, panel_title)
        tables.append(rows)
    violent = [r for r in read_csv(os.path.join(data, "stability_violent.csv")) if r["method"] == method]
    class_map(axes[-1], violent, "constant_speed_rad_per_s", "friction_coefficient",
              "constant speed from rest, 1 s, rtol 1e-6")
    tables.append(violent)
    legend(fig, {q["status"] for rows in tables for q in rows})
    fig.suptitle(title, x=0.3)
    fig.tight_layout(rect=(0, 0.03, 1, 0.93))
    stamp(fig, text)
    fig.savefig(os.path.join(out, "stability_%s.png" % method), dpi=100)
    plt.close(fig)
    return tables


def switching(data, out, text):
    return method_figure(data, out, text, "switching", "switching method (II): where it fails", [
        ("switching_restitution", "restitution", "friction_coefficient", "restitution x friction, rtol 1e-6"),
        ("switching_grazing", "eccentricity_m", "rtol", "grazing: unbalance near the touching one x rtol")])


def iteration(data, out, text):
    return method_figure(data, out, text, "iteration", "iteration method (III): where it fails", [
        ("iteration_force_tolerance", "iteration_force_rtol", "friction_coefficient",
         "force root tolerance x friction"),
        ("iteration_step", "rtol", "friction_coefficient", "step size (rtol) x friction")])


def stick_slip(data, out, text):
    """The stick-slip map: class per (speed, friction) for each method, each
    cell labelled with the share of its contact time spent sticking."""
    rows = read_csv(os.path.join(data, "stability_stick_slip.csv"))
    methods = ("switching", "iteration", "penalty")
    fig, axes = plt.subplots(1, 3, figsize=(17, 5.6))
    for ax, method in zip(axes, methods):
        mine = [r for r in rows if r["method"] == method]
        class_map(ax, mine, "constant_speed_rad_per_s", "friction_coefficient",
                  "%s: constant speed from rest, 1 s, rtol 1e-6" % method)
        xs = sorted({value(r, "constant_speed_rad_per_s") for r in mine})
        ys = sorted({value(r, "friction_coefficient") for r in mine})
        for r in mine:
            if r["status"] not in COMPLETED:
                continue
            contact = float(r["contact_time_s"] or 0)
            share = float(r["stick_time_s"] or 0) / contact if contact > 0 else 0.0
            label = "-" if contact == 0 else "%.0f" % (100 * share)
            ax.text(xs.index(value(r, "constant_speed_rad_per_s")), ys.index(value(r, "friction_coefficient")),
                    label, ha="center", va="center", fontsize=7)
    legend(fig, {q["status"] for q in rows})
    fig.suptitle("stick and slip: class per (speed, friction); number: % of contact time sticking "
                 "(rolling), '-': no contact", x=0.4)
    fig.tight_layout(rect=(0, 0.03, 1, 0.93))
    stamp(fig, text)
    fig.savefig(os.path.join(out, "stability_stick_slip.png"), dpi=100)
    plt.close(fig)
    return rows


def summary(name, rows):
    counts = {}
    for r in rows:
        counts[r["status"]] = counts.get(r["status"], 0) + 1
    return "%s: %d runs: %s" % (name, len(rows), ", ".join("%s %d" % kv for kv in sorted(counts.items())))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--data", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--stamp", required=True)
    ap.add_argument("--scene", default="")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    for k, stable, bad, theory in penalty(a.data, a.out, a.stamp, a.scene):
        print("penalty rk4 k_c %.0e N/m: completes up to h = %s s, then %s s; theory h_max = %.3g s"
              % (k, "%.3g" % stable if stable else "none", bad if bad else "none", theory))
    for name, rows in zip(("switching restitution x friction", "switching grazing", "switching violent"),
                          switching(a.data, a.out, a.stamp)):
        print(summary(name, rows))
    for name, rows in zip(("iteration force tolerance", "iteration step", "iteration violent"),
                          iteration(a.data, a.out, a.stamp)):
        print(summary(name, rows))
    for method in ("switching", "iteration", "penalty"):
        print(summary("stick-slip " + method, [r for r in stick_slip(a.data, a.out, a.stamp) if r["method"] == method]))
    for name in ("stability_penalty_adaptive", "stability_violent"):
        print(summary(name, read_csv(os.path.join(a.data, name + ".csv"))))
    print("stability maps written to", a.out)


if __name__ == "__main__":
    main()
