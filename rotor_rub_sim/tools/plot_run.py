#!/usr/bin/env python3
"""plot_run: pictures of one run, from a bag the node recorded or from the
headless runner's CSV: x_r(t) and y_r(t) with contact shaded, the orbit inside
the clearance circle, the normal force, the speed, and a full-spectrum
waterfall (forward and backward whirl against speed) -- the plots
rotordynamics engineers read first. PNGs into the folder named.

usage: plot_run.py RUN.bag|RUN.csv --out DIR [--ns /rotor_rub_sim] [--clearance M]
                   [--window-s 0.25] [--title TEXT]
  A bag: the states of <ns>/state (with several runs in the bag and no --ns,
  the first in name order, and it says so). A CSV: rotor_rub_run --csv output.
  The clearance is the run's own (its penetration = |r_r - r_s| - C, sample by
  sample: a live change shows) unless --clearance overrides it. From a bag,
  the live changes and faults the node applied (parameter_change_feedback)
  are marked with a dotted line and their keys.
Full spectrum: the FFT of the complex displacement z = x_r + i y_r over sliding
Hann windows; positive frequencies are forward whirl, negative backward.
Exit status 2 on an unreadable input, with one line saying why."""
import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load_bag(path, ns):
    import rosbag
    with rosbag.Bag(path) as b:
        topics = b.get_type_and_topic_info().topics
        states = [t for t, i in topics.items() if i.msg_type == "rotor_rub_msgs/RotorState"
                  and not t.endswith("lockstep_state")]
        if ns:
            states = [t for t in states if t == ns.rstrip("/") + "/state"]
        if not states:
            raise ValueError("no rotor_rub_msgs/RotorState topic%s in %s" % (" " + ns + "/state" if ns else "", path))
        topic = sorted(states)[0]
        if len(states) > 1:
            print("plot_run: %s holds %d runs (%s); plotting %s (choose with --ns)"
                  % (path, len(states), ", ".join(sorted(states)), topic), file=sys.stderr)
        rows = [(m.header.stamp.to_sec(), m.rotor_position.x, m.rotor_position.y, m.stator_position.x,
                 m.stator_position.y, m.normal_force, float(m.in_contact), m.speed, m.penetration)
                for _, m, _ in b.read_messages(topics=[topic])]
        feedback = topic[:-len("state")] + "parameter_change_feedback"
        applied = [m for _, m, _ in b.read_messages(topics=[feedback]) if m.accepted]
    return topic, np.array(rows), change_spans(applied)


def change_spans(applied):
    """(start, end, label) per change the node answered: a ramp is one
    answer spanning its steps (start its first, end its last), labelled with
    the steps' count."""
    # A bag recorded before the fields end_time and steps: one entry per step.
    spans = [(m.effective_time, getattr(m, "end_time", m.effective_time), getattr(m, "steps", 1), m) for m in applied]
    return [(t0, t1, change_label(m) if n <= 1 else "%s (%d steps)" % (change_label(m), n)) for t0, t1, n, m in spans]


def change_label(m):
    """A fault by its kind, a parameter change by its keys and values."""
    if m.source.startswith("fault:"):
        return m.source[len("fault:"):]
    return ", ".join("%s %g" % (k, v) for k, v in zip(m.keys, m.values))


def mark_changes(ax, changes, label=False):
    """One mark per change: a dotted line at a step, a band over a ramp."""
    for t0, t1, text in changes:
        ax.axvline(t0, color="tab:purple", ls=":", lw=0.9)
        if t1 > t0:
            ax.axvspan(t0, t1, color="tab:purple", alpha=0.12, lw=0)
        if label:
            ax.annotate(text, (t0, 1.0), xycoords=("data", "axes fraction"), rotation=90, va="top", ha="right",
                        fontsize=7, color="tab:purple")


def load_csv(path):
    with open(path) as f:
        r = csv.DictReader(f)
        need = ["t", "x_r", "y_r", "x_s", "y_s", "normal_force", "in_contact", "speed", "penetration"]
        if not r.fieldnames or any(k not in r.fieldnames for k in need):
            raise ValueError("%s is not a rotor_rub_run CSV (needs columns %s)" % (path, ", ".join(need)))
        return os.path.basename(path), np.array([[float(row[k]) for k in need] for row in r]), []


def contact_spans(t, c):
    spans, start = [], None
    for ti, ci in zip(t, c > 0.5):
        if ci and start is None:
            start = ti
        if not ci and start is not None:
            spans.append((start, ti))
            start = None
    if start is not None:
        spans.append((start, t[-1]))
    return spans


def shade(ax, spans):
    for a, b in spans:
        ax.axvspan(a, b, color="0.6", alpha=0.35, lw=0)


CLEARANCE_COLOURS = ("k", "tab:red", "tab:purple", "tab:orange", "tab:green", "tab:brown")


def clearance_levels(t, c_t, ramps=(), most=len(CLEARANCE_COLOURS)):
    """The clearances in force over the run, each with the time it began: a
    new level where C moves by more than 1e-9 of itself (the samples' C is
    |r_r - r_s| - penetration, exact to rounding). A ramp (start, end) in ramps
    gives one, where it ended (its steps begin at most a sample and a half
    after theirs); beyond `most` levels: the first, the last and evenly
    spaced ones between."""
    levels = [(float(t[0]), float(c_t[0]))]
    for ti, ci in zip(t[1:], c_t[1:]):
        if abs(ci - levels[-1][1]) > 1e-9 * abs(levels[-1][1]):
            levels.append((float(ti), float(ci)))
    dt = float(np.median(np.diff(t))) if len(t) > 1 else 0.0
    for t0, t1 in ramps:
        inside = [k for k, (ti, _) in enumerate(levels) if k > 0 and t0 <= ti <= t1 + 1.5 * dt]
        levels = [lv for k, lv in enumerate(levels) if k not in inside[:-1]]
    if len(levels) > most:
        keep = np.unique(np.round(np.linspace(0, len(levels) - 1, most)).astype(int))
        levels = [levels[k] for k in keep]
    return levels


def main():
    ap = argparse.ArgumentParser(description="Pictures of one run (displacement, orbit, force and speed, "
                                 "full-spectrum waterfall) as PNGs.")
    ap.add_argument("run", help="a bag the node recorded, or a rotor_rub_run --csv file")
    ap.add_argument("--out", required=True, help="folder for the PNGs (made if missing)")
    ap.add_argument("--ns", default="", help="the run's namespace in a bag of several, e.g. /switching")
    ap.add_argument("--clearance", type=float, default=None,
                    help="clearance C [m] drawn on the plots; default: the run's own, from its penetration")
    ap.add_argument("--window-s", type=float, default=0.25, help="waterfall window [s] of simulated time")
    ap.add_argument("--title", default="", help="title prefix (default: the run's name)")
    a = ap.parse_args()
    try:
        name, d, changes = load_bag(a.run, a.ns) if a.run.endswith(".bag") else load_csv(a.run)
    except Exception as e:  # an unreadable input is a clear error, not a trace
        print("plot_run: cannot read %s: %s" % (a.run, e), file=sys.stderr)
        sys.exit(2)
    if len(d) < 16:
        print("plot_run: %s holds %d states, too few to plot" % (a.run, len(d)), file=sys.stderr)
        sys.exit(2)
    os.makedirs(a.out, exist_ok=True)
    t, xr, yr, xs, ys, fn, c, w, pen = d.T
    # The run's own C at every sample (a live change moves it), or the one given.
    given = a.clearance
    c_t = np.hypot(xr - xs, yr - ys) - pen if a.clearance is None else np.full_like(t, a.clearance)
    if a.clearance is None:
        a.clearance = float(c_t[0])
    spans = contact_spans(t, c)
    title = a.title or name
    mm = 1e3

    fig, ax = plt.subplots(2, 1, figsize=(11, 5), sharex=True)
    for axis, v, lab in ((ax[0], xr, "x_r [mm]"), (ax[1], yr, "y_r [mm]")):
        axis.plot(t, v * mm, lw=0.5)
        shade(axis, spans)
        axis.plot(t, c_t * mm, color="k", ls="--", lw=0.6)
        axis.plot(t, -c_t * mm, color="k", ls="--", lw=0.6)
        mark_changes(axis, changes, label=axis is ax[0])
        axis.set_ylabel(lab)
    ax[1].set_xlabel("t [s]   (grey: in contact; dashed: the clearance%s)" %
                     ("; dotted: live changes and faults, a band over a ramp" if changes else ""))
    ax[0].set_title(title + ": rotor displacement")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "displacement.png"), dpi=100)
    plt.close(fig)

    fig, ax = plt.subplots(1, 2, figsize=(10, 5))
    th = np.linspace(0, 2 * np.pi, 400)
    # Every clearance in force (a live change or a fault moves it), not only
    # the first: the orbit after a seal wear does not pass through the bore.
    ramps = [(t0, t1) for t0, t1, _ in changes if t1 > t0]
    levels = clearance_levels(t, c_t, ramps) if given is None else [(float(t[0]), given)]
    # Relative to the stator the bore is the clearance circle about 0; in the
    # casing (where the proximity probes are mounted) it moves with the
    # stator: drawn about the stator's mean position (its offset, its sag).
    for axis, (x, y), (cx, cy), lab in (
            (ax[0], (xr - xs, yr - ys), (0.0, 0.0), "relative to the stator"),
            (ax[1], (xr, yr), (np.mean(xs), np.mean(ys)),
             "in the casing (the probes' frame), the bore at the stator's mean")):
        axis.plot(x * mm, y * mm, lw=0.3)
        for k, (t0, cl) in enumerate(levels):
            axis.plot((cx + cl * np.cos(th)) * mm, (cy + cl * np.sin(th)) * mm, "--",
                      color=CLEARANCE_COLOURS[k % len(CLEARANCE_COLOURS)], lw=0.9,
                      label="C = %.4g mm from %.3f s" % (cl * mm, t0))
        if len(levels) > 1:
            axis.legend(fontsize=7, loc="upper right")
        axis.set_aspect("equal")
        axis.set_xlabel("x [mm]")
        axis.set_ylabel("y [mm]")
        axis.set_title(lab, fontsize=9)
    fig.suptitle(title + ": orbit and the clearance circle" + ("s in force" if len(levels) > 1 else ""))
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "orbit.png"), dpi=100)
    plt.close(fig)

    fig, ax = plt.subplots(2, 1, figsize=(11, 5), sharex=True)
    ax[0].plot(t, fn, lw=0.5, color="tab:red")
    shade(ax[0], spans)
    for axis in ax:
        mark_changes(axis, changes, label=axis is ax[0])
    ax[0].set_ylabel("normal force [N]")
    ax[0].set_title(title + ": contact force and speed")
    ax[1].plot(t, w, color="tab:blue")
    ax[1].set_ylabel("speed [rad/s]")
    ax[1].set_xlabel("t [s]")
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "force_speed.png"), dpi=100)
    plt.close(fig)

    # Full-spectrum waterfall over sliding Hann windows.
    dt = float(np.median(np.diff(t)))
    n = max(16, int(round(a.window_s / dt)))
    hop = max(1, n // 4)
    z = (xr + 1j * yr)
    win = np.hanning(n)
    freqs = np.fft.fftshift(np.fft.fftfreq(n, dt))
    rows, speeds, times = [], [], []
    for i in range(0, len(z) - n + 1, hop):
        seg = z[i:i + n]  # the mean stays: a static offset (gravity, a pressed rotor) shows at 0 Hz
        spec = np.abs(np.fft.fftshift(np.fft.fft(seg * win))) * 2 / win.sum()
        rows.append(spec)
        speeds.append(np.mean(w[i:i + n]) / (2 * math.pi))
        times.append(t[i + n // 2])
    fig, axis = plt.subplots(figsize=(10, 6))
    if rows:
        spec = np.array(rows) * mm
        fmax = min(freqs.max(), 4 * max(max(speeds), 1.0))
        keep = np.abs(freqs) <= fmax
        extent = (freqs[keep][0], freqs[keep][-1], 0, len(rows))
        im = axis.imshow(np.log10(spec[:, keep] + 1e-6), aspect="auto", origin="lower", extent=extent,
                         cmap="viridis")
        fig.colorbar(im, label="log10 amplitude [mm]")
        # Rows are windows in time order; each tick names the window's time
        # and spin speed (the speed alone repeats once it is held constant).
        ticks = np.linspace(0, len(rows) - 1, min(8, len(rows))).astype(int)
        axis.set_yticks(ticks + 0.5)
        axis.set_yticklabels(["%.2f s  %.1f Hz" % (times[k], speeds[k]) for k in ticks])
        # 1X lines: forward and backward synchronous whirl.
        axis.plot(speeds, np.arange(len(rows)) + 0.5, "w--", lw=0.8)
        axis.plot([-s for s in speeds], np.arange(len(rows)) + 0.5, "w:", lw=0.8)
    axis.set_xlabel("whirl frequency [Hz]  (+ forward, - backward; dashed: +1X, dotted: -1X)")
    axis.set_ylabel("window centre: time [s], spin speed [Hz]")
    axis.set_title("%s: full-spectrum waterfall (%.2f s Hann windows)" % (title, n * dt))
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "waterfall.png"), dpi=100)
    plt.close(fig)
    print("plot_run: %d states%s from %s -> %s/{displacement,orbit,force_speed,waterfall}.png"
          % (len(d), " and %d live changes" % len(changes) if changes else "", name, a.out))
    if len(levels) > 1:
        print("plot_run: orbit.png draws %d clearances in force: %s" % (
            len(levels), ", ".join("%.4g mm from %.3f s" % (cl * mm, t0) for t0, cl in levels)))


if __name__ == "__main__":
    main()
