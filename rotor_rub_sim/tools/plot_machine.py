#!/usr/bin/env python3
"""plot_machine: the pictures an engineer looks at for a (motor-driven) run,
from what the machine offers, drawn from the headless runner's CSVs:

  drive.png   speed, and the drive and friction torques, against time, with
              contact shaded (the torques when RUN.csv has the columns
              drive_torque, friction_torque; a runner without them gives the
              speed alone, and says so)
  probes.png  the X and Y probe signals [V] against time, contact shaded, the
              keyphasor's marks as ticks
  orbit.png   the orbit reconstructed from the two probes (their angles and
              sensitivity; the axes need not be orthogonal) inside the
              designed clearance circle, a dot at every keyphasor mark; beside
              it the last revolutions, where the dots read the 1X phase
  bode.png    1X amplitude and phase lag of each probe per revolution
              (synchronous DFT between keyphasor marks) against speed

usage: plot_machine.py --csv RUN.csv --probes P.csv --keyphasor K.csv --out DIR
                       [--summary RUN.json | --probe-x-angle-rad A --probe-y-angle-rad B
                        --probe-sensitivity S] [--title TEXT]
  rotor_rub_run --scene S --csv RUN.csv --probes P.csv --keyphasor K.csv [--summary RUN.json]
  The probes' angles and sensitivity are the scene's: from the run's JSON
  summary (its scene_values), or given. The clearance: the summary's, else
  the run's own (RUN.csv: penetration = |r_r - r_s| - C).
Exit status 2 on an unreadable input or a missing design value, with one
line saying why."""
import argparse
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.realpath(__file__))
sys.path[:0] = [HERE, os.path.join(HERE, "..", "examples")]  # installed: one folder; source tree: examples/
import machine_rub_detector as mrd  # noqa: E402
from plot_run import contact_spans, shade  # noqa: E402  (one folder: installed and in tools/)


def read_columns(path, need, optional=()):
    """{column: array} of a CSV with the columns `need` (an error naming the
    missing ones) and those of `optional` it has."""
    with open(path) as f:
        r = csv.reader(f)
        header = next(r, None)
        if not header or any(k not in header for k in need):
            missing = [k for k in need if k not in (header or [])]
            raise ValueError("%s lacks the column(s) %s" % (path, ", ".join(missing)))
        rows = [row for row in r if row]
    have = [k for k in list(need) + list(optional) if k in header]
    data = np.array([[float(row[header.index(k)]) for k in have] for row in rows]).reshape(-1, len(have))
    return {k: data[:, i] for i, k in enumerate(have)}


def design(a, run):
    """(geometry, clearance, where) from the summary or the flags."""
    flags = (a.probe_x_angle_rad, a.probe_y_angle_rad, a.probe_sensitivity)
    clearance = None
    if a.summary:
        with open(a.summary) as f:
            values = json.load(f).get("scene_values")
        if not isinstance(values, dict):
            raise ValueError("%s has no scene_values (is it rotor_rub_run's --summary?)" % a.summary)
        keys = ("probe_x_angle_rad", "probe_y_angle_rad", "probe_sensitivity_V_per_m")
        missing = [k for k in keys if k not in values]
        if missing:
            raise ValueError("%s: scene_values lacks %s" % (a.summary, ", ".join(missing)))
        vals = [float(values[k]) for k in keys]
        for i, v in enumerate(flags):
            if v is not None:
                vals[i] = v
        clearance = float(values["clearance_m"]) if "clearance_m" in values else None
        where = "the summary's scene_values"
    elif all(v is not None for v in flags):
        vals, where = list(flags), "given"
    else:
        raise ValueError("the probes' angles and sensitivity are the scene's: give the run's --summary JSON "
                         "(rotor_rub_run --summary) or all of --probe-x-angle-rad, --probe-y-angle-rad and "
                         "--probe-sensitivity")
    if clearance is None:
        if all(k in run for k in ("x_r", "y_r", "x_s", "y_s", "penetration")):
            clearance = float(np.hypot(run["x_r"][0] - run["x_s"][0], run["y_r"][0] - run["y_s"][0])
                              - run["penetration"][0])
        else:
            raise ValueError("no clearance: give --summary, or a RUN.csv with x_r, y_r, x_s, y_s, penetration")
    return mrd.ProbeGeometry(*vals), clearance, where


def revolutions(t, xv, yv, marks, geometry, clearance):
    """Every revolution's 1X per probe: the monitor's own analysis (the
    detector fed the probes and marks in time order)."""
    det = mrd.MachineRubDetector(clearance, geometry, None, None)
    out, mi = [], 0
    for i in range(len(t)):
        while mi < len(marks) and marks[mi][0] < t[i]:
            det.feed_keyphasor(*marks[mi])
            mi += 1
        det.feed_probes(t[i], xv[i], yv[i])
        r = det.last_revolution
        if r is not None and (not out or out[-1].revolution != r.revolution):
            out.append(r)
    return out


def main():
    ap = argparse.ArgumentParser(description="Pictures of a run from the machine's view (speed and torque, probe "
                                 "signals, probe orbit with keyphasor dots, 1X Bode plot) as PNGs.")
    ap.add_argument("--csv", required=True, help="rotor_rub_run --csv file (t, speed, in_contact; drive_torque, "
                    "friction_torque when present)")
    ap.add_argument("--probes", required=True, help="rotor_rub_run --probes file (t, x_V, y_V, ...)")
    ap.add_argument("--keyphasor", required=True, help="rotor_rub_run --keyphasor file (t, revolution, speed)")
    ap.add_argument("--out", required=True, help="folder for the PNGs (made if missing)")
    ap.add_argument("--summary", help="rotor_rub_run --summary JSON: the probes' angles, sensitivity, clearance")
    ap.add_argument("--probe-x-angle-rad", type=float, help="X probe's axis [rad] (overrides the summary)")
    ap.add_argument("--probe-y-angle-rad", type=float, help="Y probe's axis [rad] (overrides the summary)")
    ap.add_argument("--probe-sensitivity", type=float, help="probe sensitivity [V/m] (overrides the summary)")
    ap.add_argument("--title", default="", help="title prefix (default: the CSV's name)")
    a = ap.parse_args()
    try:
        run = read_columns(a.csv, ["t", "speed", "in_contact"],
                           ["drive_torque", "friction_torque", "x_r", "y_r", "x_s", "y_s", "penetration"])
        probes = read_columns(a.probes, ["t", "x_V", "y_V"])
        kp = read_columns(a.keyphasor, ["t", "revolution", "speed"])
        geometry, clearance, where = design(a, run)
    except (OSError, ValueError, StopIteration) as e:
        print("plot_machine: %s" % e, file=sys.stderr)
        sys.exit(2)
    if len(run["t"]) < 16 or len(probes["t"]) < 16:
        print("plot_machine: %d states and %d probe samples: too few to plot" % (len(run["t"]), len(probes["t"])),
              file=sys.stderr)
        sys.exit(2)
    os.makedirs(a.out, exist_ok=True)
    title = a.title or os.path.basename(a.csv)
    spans = contact_spans(run["t"], run["in_contact"])
    mm = 1e3
    drawn = []

    # Speed and torque.
    torques = [k for k in ("drive_torque", "friction_torque") if k in run]
    fig, ax = plt.subplots(2 if torques else 1, 1, figsize=(11, 5 if torques else 3), sharex=True, squeeze=False)
    ax = ax[:, 0]
    ax[0].plot(run["t"], run["speed"], color="tab:blue")
    shade(ax[0], spans)
    ax[0].set_ylabel("speed [rad/s]")
    ax[0].set_title(title + ": the drive" + ("" if torques else
                                             " (no drive_torque column in the CSV: speed only)"))
    if torques:
        for k, col in zip(torques, ("tab:green", "tab:red")):
            ax[1].plot(run["t"], run[k], lw=0.7, color=col, label=k.replace("_", " ") + " [N m]")
        shade(ax[1], spans)
        ax[1].axhline(0.0, color="k", lw=0.4)
        ax[1].set_ylabel("torque [N m]")
        ax[1].legend(loc="best", fontsize=8)
    ax[-1].set_xlabel("t [s]   (grey: in contact)")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "drive.png"), dpi=100)
    plt.close(fig)
    drawn.append("drive" + ("" if torques else " (speed only)"))

    # Probe signals.
    fig, ax = plt.subplots(2, 1, figsize=(11, 5), sharex=True)
    for axis, k, lab in ((ax[0], "x_V", "X probe [V] (%.1f deg)" % math.degrees(geometry.x_angle_rad)),
                         (ax[1], "y_V", "Y probe [V] (%.1f deg)" % math.degrees(geometry.y_angle_rad))):
        axis.plot(probes["t"], probes[k], lw=0.4)
        shade(axis, spans)
        lim = geometry.sensitivity * clearance
        axis.axhline(lim, color="k", ls="--", lw=0.6)
        axis.axhline(-lim, color="k", ls="--", lw=0.6)
        for tk in kp["t"]:
            axis.axvline(tk, ymin=0.0, ymax=0.04, color="tab:orange", lw=0.6)
        axis.set_ylabel(lab)
    ax[0].set_title(title + ": proximity probes (dashed: the clearance along the axis; ticks: keyphasor)")
    ax[1].set_xlabel("t [s]   (grey: in contact)")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "probes.png"), dpi=100)
    plt.close(fig)
    drawn.append("probes")

    # Orbit from the probes, keyphasor dots.
    x, y = geometry.displacement(probes["x_V"], probes["y_V"])
    kx = np.interp(kp["t"], probes["t"], x)
    ky = np.interp(kp["t"], probes["t"], y)
    th = np.linspace(0, 2 * np.pi, 400)
    fig, ax = plt.subplots(1, 2, figsize=(11, 5.5))
    last = kp["t"][-min(len(kp["t"]), 6)] if len(kp["t"]) else probes["t"][0]
    tail = probes["t"] >= last
    for axis, sel, ksel, lab in ((ax[0], slice(None), slice(None), "the whole run"),
                                 (ax[1], tail, kp["t"] >= last, "the last revolutions")):
        axis.plot(x[sel] * mm, y[sel] * mm, lw=0.3)
        axis.plot(kx[ksel] * mm, ky[ksel] * mm, "o", ms=3, color="tab:orange", label="keyphasor")
        axis.plot(clearance * np.cos(th) * mm, clearance * np.sin(th) * mm, "k--", lw=0.8)
        for ang, name in ((geometry.x_angle_rad, "X"), (geometry.y_angle_rad, "Y")):
            axis.annotate(name, (1.12 * clearance * math.cos(ang) * mm, 1.12 * clearance * math.sin(ang) * mm),
                          ha="center", va="center", color="tab:red")
            axis.plot([clearance * math.cos(ang) * mm, 1.05 * clearance * math.cos(ang) * mm],
                      [clearance * math.sin(ang) * mm, 1.05 * clearance * math.sin(ang) * mm], color="tab:red")
        axis.set_aspect("equal")
        axis.set_xlabel("x [mm]")
        axis.set_ylabel("y [mm]")
        axis.set_title(lab, fontsize=9)
    ax[0].legend(loc="upper right", fontsize=8)
    fig.suptitle("%s: orbit from the probes (dashed: the designed clearance, %.3g mm; probe geometry from %s)"
                 % (title, clearance * mm, where), fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "orbit.png"), dpi=100)
    plt.close(fig)
    drawn.append("orbit")

    # Bode: 1X per revolution against speed.
    marks = [(t, int(r), w) for t, r, w in zip(kp["t"], kp["revolution"], kp["speed"])]
    revs = revolutions(probes["t"], probes["x_V"], probes["y_V"], marks, geometry, clearance)
    if revs:
        sp = np.array([r.speed for r in revs])
        fig, ax = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
        for amp, lag, lab in (("x_1x_m", "x_1x_lag", "X"), ("y_1x_m", "y_1x_lag", "Y")):
            ax[0].plot(sp, np.array([getattr(r, amp) for r in revs]) * mm, ".-", ms=3, lw=0.6, label=lab)
            ax[1].plot(sp, np.degrees([getattr(r, lag) for r in revs]), ".", ms=3, label=lab)
        ax[0].axhline(clearance * mm, color="k", ls="--", lw=0.6)
        ax[0].set_ylabel("1X amplitude, 0-peak [mm]")
        ax[0].legend(fontsize=8)
        ax[0].set_title(title + ": 1X per revolution (synchronous DFT between keyphasor marks)")
        ax[1].set_ylabel("1X phase lag [deg]")
        ax[1].set_ylim(0, 360)
        ax[1].set_xlabel("speed at the revolution's end [rad/s]")
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "bode.png"), dpi=100)
        plt.close(fig)
        drawn.append("bode")
    else:
        print("plot_machine: fewer than two keyphasor marks: no bode.png", file=sys.stderr)
    print("plot_machine: %d states, %d probe samples, %d marks from %s -> %s: %s"
          % (len(run["t"]), len(probes["t"]), len(kp["t"]), a.csv, a.out, ", ".join(drawn)))


if __name__ == "__main__":
    main()
