#!/usr/bin/python3
"""rub_truncation: how many modes a flexible-rotor scene needs, judged on the
contact's quantities. Runs the scene (rotor_rub_run) at each number of planar
modes in --modes and at the reference, and prints, per model, the first
contact time, the max normal force, the max orbit radius at the rub station
and at the probe node, each with its error against the reference, then the
smallest model within --tolerance.

usage: rub_truncation.py RUNNER --scene FILE [--modes 1 2 4 8 16] [--tolerance 0.05]
                         [--quantities first_contact max_force orbit_station orbit_probe]
                         [--method M] [--set KEY=VALUE]... [--rate HZ] [--modal PATH] [--csv OUT]

The reference is the rotor's full FE model when its planar modes (half its
DOF) are 512 or fewer: with every mode kept, the Craig-Bampton reduction is
exact. A rotor with more runs at most 512 (rotor_planar_modes' range): the
reference is then 512 planar modes, the largest model the runner takes, and it
is called that, not the full model.

Tolerance: the forces and the orbits relative to the reference's value; the
first contact within --tolerance of a revolution, at the spin speed of the
reference's first contact (0.05: 18 deg of the rotor's turn). The
recommendation is the smallest model from which on every model run is within
the tolerance on every quantity judged (--quantities, default all four): a
model that agrees by chance while a larger one does not is not recommended.
When none is, it says so and names the quantity that does not converge.

What is read: each run's summary (first_contact_s, max_normal_force_N and
max_orbit_m, |r_r| at the station, both over the samples), its samples (the
spin speed at the reference's first contact) and its probes CSV (x_m, y_m):
the samples CSV does not carry the probe node's displacement, so each run is
made with probe_rate_hz = the sample rate, the probes' axes along x and y and
no runout, which makes x_m, y_m the probe node's displacement (the probes do
not change the solution). The probe node is rotor_probe_node (-1: the rotor
file's first probe, else the station).

The linear truncation study (frequencies, unbalance response) is
rotor_rub_modal --study; this one is the non-linear run's.

Exit status: 0 a model recommended; 1 none within the tolerance; 2 bad input
(one line naming the option, the value and what is accepted; or the runner's
own bad-input message); 3 a run failed (the runner's status and stderr)."""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys
import tempfile

import numpy as np
import yaml

PROG = "rub_truncation.py"
MAX_MODES = 512  # rotor_planar_modes' range: [1, 512]
QUANTITIES = ("first_contact", "max_force", "orbit_station", "orbit_probe")
DEFAULT_MODES = (1, 2, 4, 8, 16)


class BadInput(Exception):
    pass


class RunFailed(Exception):
    def __init__(self, message, status):
        super().__init__(message)
        self.status = status


class Parser(argparse.ArgumentParser):
    def error(self, message):
        # One line, the option first: "rub_truncation.py: --tolerance: value ..."
        message = re.sub(r"^argument ([^:]+): ", lambda m: m.group(1).split("/")[-1] + ": ", message)
        print("%s: %s" % (PROG, message), file=sys.stderr)
        sys.exit(2)


def number_in(lo, hi, lo_open, what):
    accepted = "%s%g, %g]" % ("(" if lo_open else "[", lo, hi)

    def parse(text):
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError("value '%s' is not a number; accepted: %s" % (text, accepted))
        if not (v > lo if lo_open else v >= lo) or not v <= hi or math.isnan(v):
            raise argparse.ArgumentTypeError("value '%s' is out of range; accepted: %s (%s)" % (text, accepted, what))
        return v
    return parse


def mode_count(text):
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError("value '%s' is not an integer; accepted: integers in [1, %d]"
                                         % (text, MAX_MODES - 1))
    if not 1 <= v < MAX_MODES:
        raise argparse.ArgumentTypeError("value '%s' is out of range; accepted: integers in [1, %d] (rotor_planar_modes "
                                         "below the reference, which has at most %d; a smaller rotor allows fewer)"
                                         % (text, MAX_MODES - 1, MAX_MODES))
    return v


def key_value(text):
    if "=" not in text or text.startswith("="):
        raise argparse.ArgumentTypeError("value '%s' is not KEY=VALUE; accepted: a scene key, '=', its value" % text)
    if text.split("=", 1)[0] == "rotor_planar_modes":
        raise argparse.ArgumentTypeError("value '%s': rotor_planar_modes is the tool's to set; accepted: any other "
                                         "scene key (the modes: --modes)" % text)
    return text


def scene_values(scene, sets):
    """The scene file's keys with --set applied (the runner's rule: a relative
    rotor_file in the file is the file's directory's, on --set the current
    directory's)."""
    try:
        with open(scene) as f:
            values = yaml.safe_load(f) or {}
    except (OSError, yaml.YAMLError) as e:
        raise BadInput("--scene: value '%s' cannot be read (%s); accepted: a scene file" % (scene, e))
    if not isinstance(values, dict):
        raise BadInput("--scene: value '%s' is not a scene (a flat YAML map of scene keys)" % scene)
    values = {str(k): v for k, v in values.items()}
    rf = values.get("rotor_file")
    if rf and not os.path.isabs(str(rf)):
        values["rotor_file"] = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(scene)), str(rf)))
    for kv in sets:
        k, v = kv.split("=", 1)
        values[k] = os.path.abspath(v) if k == "rotor_file" and v else v
    return values


def rotor_size(modal, rotor_file):
    """(planar modes of the full FE model, DOF), from rotor_rub_modal's first line."""
    r = subprocess.run([modal, "--rotor", rotor_file, "--speeds", "2", "--modes", "1", "--max-speed", "1"],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        raise BadInput("rotor_file: value '%s' is not accepted: %s" % (rotor_file, r.stderr.strip()))
    m = re.search(r"(\d+) DOF", r.stdout.split("\n", 1)[0])
    if not m:
        raise RunFailed("%s printed no DOF count for %s: %s" % (modal, rotor_file, r.stdout[:200]), 3)
    dof = int(m.group(1))
    return dof // 2, dof


def probe_node_text(values, rotor_file):
    node = int(float(values.get("rotor_probe_node", -1)))
    if node >= 0:
        return "node %d (rotor_probe_node)" % node
    try:
        with open(rotor_file) as f:
            rotor = yaml.safe_load(f) or {}
        probes = rotor.get("probes") or []
        if probes:
            return "node %d (the rotor file's first probe)" % int(probes[0]["node"])
        return "node %d (the rub station: the rotor file has no probes)" % int(rotor["rub_station"]["node"])
    except (OSError, yaml.YAMLError, KeyError, TypeError, ValueError):
        return "rotor_probe_node -1 (the rotor file's first probe, else the station)"


def read_columns(path, names):
    with open(path) as f:
        rows = list(csv.reader(f))
    if not rows:
        raise RunFailed("%s is empty" % path, 3)
    missing = [n for n in names if n not in rows[0]]
    if missing:
        raise RunFailed("%s lacks the column(s) %s" % (path, ", ".join(missing)), 3)
    idx = [rows[0].index(n) for n in names]
    data = np.array([[float(r[i]) for i in idx] for r in rows[1:]], dtype=float).reshape(-1, len(names))
    return data


def run_model(a, modes, rate, tmp):
    p = os.path.join(tmp, "m%02d" % modes)
    cmd = [a.runner, "--scene", a.scene]
    for kv in a.set:
        cmd += ["--set", kv]
    cmd += ["--set", "rotor_planar_modes=%d" % modes, "--set", "probe_rate_hz=%r" % rate,
            "--set", "probe_x_angle_rad=0", "--set", "probe_y_angle_rad=%r" % (math.pi / 2),
            "--set", "probe_runout_m=0", "--rate", "%r" % rate,
            "--csv", p + ".csv", "--probes", p + ".p.csv", "--summary", p + ".json", "--quiet"]
    if a.method:
        cmd += ["--method", a.method]
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        err = r.stderr.strip() or "(no stderr)"
        if r.returncode == 2:
            raise RunFailed("rotor_rub_run refused the run at %d planar modes: %s" % (modes, err), 2)
        raise RunFailed("the run at %d planar modes failed (rotor_rub_run exit status %d): %s"
                        % (modes, r.returncode, err), 3)
    with open(p + ".json") as f:
        s = json.load(f)
    samples = read_columns(p + ".csv", ["t", "speed"])
    probes = read_columns(p + ".p.csv", ["x_m", "y_m"])
    fc = s.get("first_contact_s")
    return {
        "modes": modes,
        "first_contact_s": fc,
        "speed_at_first_contact": (float(np.interp(fc, samples[:, 0], samples[:, 1]))
                                   if fc is not None and len(samples) else None),
        "max_force": float(s.get("max_normal_force_N") or 0.0),
        "orbit_station": float(s.get("max_orbit_m") or 0.0),
        "orbit_probe": float(np.max(np.hypot(probes[:, 0], probes[:, 1]))) if len(probes) else 0.0,
        "wall_s": float(s["stats"]["wall_time_s"]),
        "method": s.get("method"),
        "integrator": s.get("integrator"),
    }


def relative(v, ref):
    if ref == 0.0:
        return 0.0 if v == 0.0 else math.inf
    return abs(v - ref) / abs(ref)


def judge(rows, ref, tol, quantities):
    """Errors of every row against ref, and which quantities each row has within."""
    t_ref = ref["first_contact_s"]
    w = ref["speed_at_first_contact"]
    if t_ref is not None and w is not None and abs(w) > 0.0:
        t_bound = tol * 2.0 * math.pi / abs(w)
        t_text = ("within %g of a revolution at the reference's first-contact speed (%.1f rad/s): %.3g s"
                  % (tol, w, t_bound))
    elif t_ref is not None:
        t_bound = tol * abs(t_ref)
        t_text = "within %g of the reference's first-contact time (no spin then): %.3g s" % (tol, t_bound)
    else:
        t_bound = 0.0
        t_text = "none in the reference: a model within has none either"
    for r in rows:
        t = r["first_contact_s"]
        if t is None and t_ref is None:
            r["err_first_contact"] = 0.0
        elif t is None or t_ref is None:
            r["err_first_contact"] = math.inf
        else:
            r["err_first_contact"] = t - t_ref
        r["within_first_contact"] = abs(r["err_first_contact"]) <= t_bound
        for q in ("max_force", "orbit_station", "orbit_probe"):
            r["err_" + q] = relative(r[q], ref[q])
            r["within_" + q] = r["err_" + q] <= tol
        r["within"] = all(r["within_" + q] for q in quantities)
    return t_text


def recommend(rows, quantities):
    """The smallest model from which on every model run (the reference
    excluded) is within; None when the largest is not."""
    best = None
    for r in reversed(rows):
        if not r["within"]:
            break
        best = r
    return best


def fmt_err(r, q, quantities, rel=True):
    e = r["err_" + q]
    text = ("%.2e" % e if rel else "%+.2e" % e) if math.isfinite(e) else "inf"
    return text + ("*" if q in quantities and not r["within_" + q] else " ")


def fmt_t(t):
    return "%.6f" % t if t is not None else "none"


def main(argv=None):
    ap = Parser(prog=PROG, description=__doc__.split("\n\n")[0],
                epilog="Exit status: 0 a model recommended; 1 none within the tolerance; 2 bad input; "
                       "3 a run failed. docs/tools.md.")
    ap.add_argument("runner", metavar="RUNNER", help="rotor_rub_run (its path)")
    ap.add_argument("--scene", required=True, help="the scene file (with rotor_file)")
    ap.add_argument("--modes", type=mode_count, nargs="+", metavar="N",
                    help="planar modes of the models to judge, integers in [1, 511] below the reference "
                         "(default: 1 2 4 8 16, those below the reference)")
    ap.add_argument("--tolerance", type=number_in(0.0, 1.0, True, "relative; first contact: of a revolution"),
                    default=0.05,
                    help="(0, 1], default 0.05: forces and orbits relative to the reference's; first contact in "
                         "revolutions at the reference's first-contact speed")
    ap.add_argument("--quantities", nargs="+", metavar="Q", default=list(QUANTITIES),
                    help="the quantities judged, any of %s (default: all); the others are printed, not judged"
                         % " ".join(QUANTITIES))
    ap.add_argument("--method", help="contact method, one the runner accepts (default: the scene's)")
    ap.add_argument("--set", action="append", default=[], type=key_value, metavar="KEY=VALUE",
                    help="a scene key for every run (rotor_rub_run --set), repeatable; not rotor_planar_modes")
    ap.add_argument("--rate", type=number_in(0.0, 1e7, True, "Hz"),
                    help="sample rate of the samples and the probes [Hz] (default: the scene's output_rate_hz, "
                         "1000 without one); the maxima are over these samples")
    ap.add_argument("--modal", help="rotor_rub_modal, for the rotor's DOF (default: beside RUNNER)")
    ap.add_argument("--csv", metavar="OUT", help="write the table, one row per model, to this CSV file")
    a = ap.parse_args(argv)
    try:
        return study(a)
    except BadInput as e:
        print("%s: %s" % (PROG, e), file=sys.stderr)
        return 2
    except RunFailed as e:
        print("%s: %s" % (PROG, e), file=sys.stderr)
        return e.status


def runner_methods(runner):
    """The contact methods the runner accepts: its key table's `method` line
    (rotor_rub_run --list-keys: 'method  default ...  accepted one of A B C')."""
    keys = subprocess.run([runner, "--list-keys"], check=True, capture_output=True, text=True).stdout
    for line in keys.splitlines():
        if line.startswith("method ") and "accepted one of" in line:
            return line.split("accepted one of", 1)[1].split()
    raise BadInput("RUNNER: '%s --list-keys' names no method key" % runner)


def study(a):
    for q in a.quantities:
        if q not in QUANTITIES:
            raise BadInput("--quantities: value '%s' is not accepted; accepted: any of %s" % (q, " ".join(QUANTITIES)))
    quantities = list(dict.fromkeys(a.quantities))
    if not (os.path.isfile(a.runner) and os.access(a.runner, os.X_OK)):
        raise BadInput("RUNNER: value '%s' is not an executable file; accepted: the path of rotor_rub_run" % a.runner)
    if a.method is not None and a.method not in runner_methods(a.runner):
        raise BadInput("--method: value '%s' is not accepted; accepted: one of %s"
                       % (a.method, " ".join(runner_methods(a.runner))))
    modal = a.modal or os.path.join(os.path.dirname(os.path.abspath(a.runner)), "rotor_rub_modal")
    if not (os.path.isfile(modal) and os.access(modal, os.X_OK)):
        raise BadInput("--modal: value '%s' is not an executable file; accepted: the path of rotor_rub_modal" % modal)
    values = scene_values(a.scene, a.set)
    rotor_file = values.get("rotor_file")
    if not rotor_file:
        raise BadInput("--scene: value '%s' has no rotor_file; accepted: a scene of a flexible rotor "
                       "(scene key rotor_file, docs/rotors.md)" % a.scene)
    full, dof = rotor_size(modal, rotor_file)
    ref_modes = min(full, MAX_MODES)
    if a.modes is None:
        modes = [m for m in DEFAULT_MODES if m < ref_modes]
    else:
        modes = sorted(set(a.modes))
        over = [m for m in modes if m >= ref_modes]
        if over:
            raise BadInput("--modes: value %d is not below the reference (%d planar modes); accepted: integers in "
                           "[1, %d] for this rotor" % (over[0], ref_modes, ref_modes - 1))
    if not modes:
        raise BadInput("--modes: no model below the reference (%d planar modes): the rotor has nothing to truncate"
                       % ref_modes)
    rate = a.rate or float(values.get("output_rate_hz", 1000.0))
    if ref_modes == full:
        ref_text = "the full FE model (%d planar modes, %d DOF: every mode kept)" % (full, dof)
    else:
        ref_text = ("%d planar modes, the largest model the runner takes (not the full FE model, which has %d planar "
                    "modes, %d DOF)" % (ref_modes, full, dof))

    with tempfile.TemporaryDirectory(prefix="rub_truncation_") as tmp:
        ref = run_model(a, ref_modes, rate, tmp)
        rows = [run_model(a, m, rate, tmp) for m in modes]
    t_text = judge(rows + [ref], ref, a.tolerance, quantities)

    print("%s: %s on %s, %s (%s)" % (PROG, a.scene, rotor_file, ref["method"], ref["integrator"]))
    print("reference: " + ref_text)
    print("probe: %s; orbits: max radius over the samples at %g Hz" % (probe_node_text(values, rotor_file), rate))
    print("tolerance %g: max F_n and orbits relative to the reference's; first contact %s"
          % (a.tolerance, t_text))
    print("judged: %s (* beyond the tolerance)" % ", ".join(quantities))
    head = "%7s %12s %10s %8s %10s %11s %10s %11s %10s %8s" % (
        "modes", "1st contact", "error", "max F_n", "error", "station", "error", "probe", "error", "wall")
    unit = "%7s %12s %10s %8s %10s %11s %10s %11s %10s %8s" % (
        "", "[s]", "[s]", "[N]", "[rel]", "orbit [m]", "[rel]", "orbit [m]", "[rel]", "[s]")
    print(head)
    print(unit)
    for r in rows + [ref]:
        print("%7s %12s %10s %8.2f %10s %11.4e %10s %11.4e %10s %8.3f" % (
            ("%d" if r is not ref else "%d ref") % r["modes"], fmt_t(r["first_contact_s"]),
            fmt_err(r, "first_contact", quantities, rel=False), r["max_force"],
            fmt_err(r, "max_force", quantities), r["orbit_station"], fmt_err(r, "orbit_station", quantities),
            r["orbit_probe"], fmt_err(r, "orbit_probe", quantities), r["wall_s"]))

    if a.csv:
        try:
            with open(a.csv, "w", newline="") as f:
                w = csv.writer(f)
                w.writerow(["planar_modes", "reference", "first_contact_s", "first_contact_err_s",
                            "max_normal_force_N", "max_normal_force_err_rel", "max_orbit_station_m",
                            "max_orbit_station_err_rel", "max_orbit_probe_m", "max_orbit_probe_err_rel",
                            "wall_time_s", "within"])
                for r in rows + [ref]:
                    fc = r["first_contact_s"]
                    w.writerow([r["modes"], int(r is ref), repr(fc) if fc is not None else ""] +
                               [repr(r[k]) for k in ("err_first_contact", "max_force", "err_max_force", "orbit_station",
                                                     "err_orbit_station", "orbit_probe", "err_orbit_probe", "wall_s")] +
                               [int(r["within"])])
        except OSError as e:
            raise BadInput("--csv: value '%s' cannot be written (%s)" % (a.csv, e.strerror))

    best = recommend(rows, quantities)
    unjudged = [q for q in QUANTITIES if q not in quantities]
    if best is not None:
        line = ("recommended: %d planar mode%s (%d coordinates): from %d on, every model run is within %g of the "
                "reference on %s" % (best["modes"], "" if best["modes"] == 1 else "s", 2 * best["modes"],
                                     best["modes"], a.tolerance, ", ".join(quantities)))
        if unjudged:
            line += "; not judged: " + ", ".join(
                "%s (error %s at %d)" % (q, fmt_err(best, q, quantities).strip(), best["modes"]) for q in unjudged)
        print(line)
        return 0
    last = rows[-1]
    failing = [q for q in quantities if not last["within_" + q]]
    errors = ", ".join("%s error %s" % (q, fmt_err(last, q, quantities).strip().rstrip("*")) for q in failing)
    after = ("only the full FE model, the reference, is within" if ref_modes == full else
             "the reference (%d of %d planar modes) is not shown to be converged either" % (ref_modes, full))
    print("recommended: none: %s %s not converge within %g (at %d planar mode%s, the largest below the reference: "
          "%s); %s" % (" and ".join(failing), "does" if len(failing) == 1 else "do", a.tolerance, last["modes"],
                       "" if last["modes"] == 1 else "s", errors, after))
    return 1


if __name__ == "__main__":
    sys.exit(main())
