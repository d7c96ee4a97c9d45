#!/usr/bin/python3
"""Draws rotor_rub_modal's CSVs: the Campbell diagram (damped natural
frequencies against speed, forward whirl solid, backward dashed, mixed
dotted, with the synchronous line w = Omega whose crossings are the critical
speeds), if given the unbalance response at a node (forward and backward
1X, |x| and |y|) against speed, and the mode shapes at rest (x and y along
the shaft, one panel per mode).

usage: plot_campbell.py CAMPBELL.csv [--response RESPONSE.csv] [--shapes SHAPES.csv] --out DIR [--title TEXT]"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path, need):
    with open(path) as f:
        r = csv.DictReader(f)
        if not r.fieldnames or any(k not in r.fieldnames for k in need):
            raise ValueError("%s lacks the columns %s (is it rotor_rub_modal's?)" % (path, ", ".join(need)))
        return list(r)


def main():
    ap = argparse.ArgumentParser(description="Campbell diagram and unbalance response from rotor_rub_modal's CSVs.")
    ap.add_argument("campbell", help="rotor_rub_modal --campbell output")
    ap.add_argument("--response", help="rotor_rub_modal --response output")
    ap.add_argument("--shapes", help="rotor_rub_modal --shapes output")
    ap.add_argument("--out", required=True, help="folder for campbell.png (and response.png, shapes.png)")
    ap.add_argument("--title", default="", help="title prefix")
    a = ap.parse_args()
    try:
        rows = read(a.campbell, ["speed_rad_per_s", "mode", "damped_frequency_rad_per_s", "whirl"])
        response = read(a.response, ["speed_rad_per_s", "forward_m", "backward_m", "x_m", "y_m"]) if a.response else []
        shapes = read(a.shapes, ["mode", "z_m", "x_re", "y_re", "damped_frequency_rad_per_s", "whirl"]) if a.shapes else []
    except (OSError, ValueError) as e:
        print("plot_campbell: %s" % e, file=sys.stderr)
        sys.exit(2)
    os.makedirs(a.out, exist_ok=True)
    modes = {}
    for r in rows:
        modes.setdefault(int(r["mode"]), []).append(
            (float(r["speed_rad_per_s"]), float(r["damped_frequency_rad_per_s"]), r["whirl"]))
    fig, ax = plt.subplots(figsize=(8, 6))
    style = {"forward": "-", "backward": "--", "mixed": ":"}
    top = 0.0
    for k, pts in sorted(modes.items()):
        # Each segment in its own style: a mode may change its whirl with speed.
        for (s0, w0, h0), (s1, w1, _) in zip(pts, pts[1:]):
            ax.plot([s0, s1], [w0, w1], style.get(h0, "-"), color="C%d" % (k % 10), lw=1.2)
        ax.plot([], [], "-", color="C%d" % (k % 10), label="mode %d" % k)
        top = max(top, max(w for _, w, _ in pts))
    smax = max(float(r["speed_rad_per_s"]) for r in rows)
    ax.plot([0, smax], [0, smax], "k-", lw=0.8, label="synchronous (1X)")
    ax.set_xlim(0, smax)
    ax.set_ylim(0, top * 1.05)
    ax.set_xlabel("speed [rad/s]")
    ax.set_ylabel("damped natural frequency [rad/s]")
    ax.set_title((a.title + ": " if a.title else "") + "Campbell diagram (solid forward, dashed backward whirl)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(a.out, "campbell.png"), dpi=100)
    plt.close(fig)
    if response:
        s = [float(r["speed_rad_per_s"]) for r in response]
        fig, ax = plt.subplots(figsize=(8, 5))
        for key, lab, ls in (("forward_m", "forward 1X", "-"), ("backward_m", "backward 1X", "--"),
                             ("x_m", "|x|", ":"), ("y_m", "|y|", "-.")):
            ax.semilogy(s, [max(float(r[key]), 1e-15) for r in response], ls, label=lab)
        ax.set_xlabel("speed [rad/s]")
        ax.set_ylabel("amplitude [m]")
        ax.set_title((a.title + ": " if a.title else "") + "unbalance response")
        ax.legend()
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "response.png"), dpi=100)
        plt.close(fig)
    if shapes:
        by_mode = {}
        for r in shapes:
            by_mode.setdefault(int(r["mode"]), []).append(r)
        n = len(by_mode)
        fig, axes = plt.subplots(n, 1, figsize=(8, 1.8 * n + 0.6), sharex=True, squeeze=False)
        for ax, (k, pts) in zip(axes[:, 0], sorted(by_mode.items())):
            z = [float(r["z_m"]) for r in pts]
            ax.plot(z, [float(r["x_re"]) for r in pts], "o-", ms=3, label="x")
            ax.plot(z, [float(r["y_re"]) for r in pts], "s--", ms=3, label="y")
            ax.axhline(0.0, color="k", lw=0.5)
            ax.set_ylabel("mode %d" % k)
            ax.set_title("%.2f rad/s, %s" % (float(pts[0]["damped_frequency_rad_per_s"]), pts[0]["whirl"]), fontsize=9)
            ax.legend(fontsize=7, loc="upper right")
        axes[-1, 0].set_xlabel("z along the shaft [m]")
        fig.suptitle((a.title + ": " if a.title else "") + "mode shapes at rest (real parts)")
        fig.tight_layout()
        fig.savefig(os.path.join(a.out, "shapes.png"), dpi=100)
        plt.close(fig)
    made = ["campbell.png"] + (["response.png"] if response else []) + (["shapes.png"] if shapes else [])
    print("plot_campbell: %d modes -> %s/%s" % (len(modes), a.out, ", ".join(made)))


if __name__ == "__main__":
    main()
