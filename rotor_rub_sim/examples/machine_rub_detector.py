"""Rub detection from what a machine offers (no ROS here): the X/Y proximity
probes' voltages, the keyphasor (one mark per revolution, with the speed),
and the drive's speed and torque. Never the rotor's position relative to the
stator, the contact force or the contact flag: a machinery-protection system
sees none of them.

Design data (what a real monitor is configured with): the radial clearance C,
the probes' angles on the casing (counter-clockwise from +x) and their
sensitivity [V/m] (ProbeGeometry). The monitor node reads them from the
simulator's parameters; the offline replay (main below) from the runner's
JSON summary.

The displacement. Each probe measures the rotor centre's displacement along
its own axis u = (cos a, sin a): v = S (d . u) + noise. Two probes whose axes
are not parallel give d = (x, y) by solving the 2x2 system; the axes need not
be orthogonal (API 670 mounts them 90 deg apart, at 45 deg either side of
top; a machine may not).

Four channels judge rub; each has its own hysteresis, and the alarm is raised
while any channel is (`reasons()` names them):

  orbit_at_clearance (every probe sample): over the last `window_s` (20 ms),
    the share of samples whose |d| >= `touch_ratio` (0.995) C. Raised at a
    share >= `raise_fraction` (0.5), cleared below `clear_fraction` (0.1):
    the rotor presses on the bore of a centred casing (full annular rub, a
    heavy local rub). Needs a whole window.
  orbit_distorted (every keyphasor mark): the orbit over the last
    `revolutions` (4) revolutions, resampled on the spin angle from the
    marks and Hann-windowed, split into its synchronous harmonics
    z = sum_h Z_h e^{i h phi}. An unbalance orbit of an isotropic machine is
    a forward circle (Z_1 only); a rub on one side flattens it: the
    distortion sqrt(|Z_-1|^2 + |Z_+-2|^2 + |Z_+-3|^2) / |Z_1| (backward 1X,
    2X and 3X against the forward 1X) >= `distortion_raise` (0.1) raises,
    < `distortion_clear` (0.05) clears. Judged only while |Z_1| >=
    `min_1x_ratio` (0.05) C (no verdict on a slow-roll orbit of noise), and
    while the probes' noise could make at most half of `distortion_clear`:
    its level from the span's second differences (their median, which an
    impact's few samples do not move), its share of each harmonic's estimate
    sqrt(sum w^2) / sum w, over the four or five orders against Z_1. Noise
    alone then neither raises nor holds the alarm (a bearing's orbit of
    1 um under 1.3 um of noise read as 0.3 to 2 of distortion).
    Non-synchronous motion (the free whirl after a start or the critical
    speed) falls between the orders and the Hann window keeps it out.
  backward_whirl (every keyphasor mark): the full spectrum of
    z = x + i y over the same revolutions (mean removed): the share of its
    power at negative (backward) frequencies >= `backward_raise` (0.6) while
    the orbit reaches `whirl_orbit_ratio` (0.5) C raises; a share below
    `backward_clear` (0.4), or the orbit below 0.8 x that ratio, clears: dry
    whirl, the rotor rolling backward on the bore.
  drive_braking (every drive sample): a rub is a braking torque. The drive
    torque is first averaged over the last revolution (2 pi / speed), which
    removes the once-per-revolution torque an unbalanced rotor's whirl asks
    of its drive. The torque rise is that torque's mean over the last
    `window_s` minus its running
    baseline (a straight line fitted to the `baseline_s` (0.5 s) before that
    window, evaluated at the window's centre, or the lowest torque of that
    baseline's last two revolutions where that is higher: a line fitted
    across a step down undershoots the new level); the speed dip is the speed's
    own baseline, extrapolated to now, minus the speed. A rise >=
    `torque_rise_Nm` raises unless the speed runs ahead of its baseline by
    more than `speed_tolerance_rad_per_s` (then the drive was commanded to
    accelerate harder, and the torque rose for that); the baseline is held
    while raised, and a rise below `torque_clear_fraction` (0.5) x
    `torque_rise_Nm` clears. A speed dip alone never raises: a prescribed
    drive reaching its target speed, or a commanded slow-down, dips the speed
    as a rub does; the torque tells them apart. A constant torque never
    raises (its rise is 0).

Deterministic: each channel's verdicts depend only on its own stream's
samples, in order (a keyphasor mark is judged once a probe sample at or
after it has arrived), and carry the simulated time they were judged at."""
import argparse
import collections
import csv
import json
import math
import sys

import numpy as np

# The simulator's scene keys the monitor needs (its design data).
MACHINE_KEYS = ("clearance_m", "probe_rate_hz", "probe_x_angle_rad", "probe_y_angle_rad",
                "probe_sensitivity_V_per_m")

# The detector's settings: name -> (default, meaning). The monitor node reads
# each as a private parameter of its own (~name).
SETTINGS = collections.OrderedDict([
    ("window_s", (0.02, "orbit_at_clearance and drive_braking: judging window [s] of simulated time")),
    ("touch_ratio", (0.995, "orbit_at_clearance: a sample touches at |d| >= touch_ratio x C")),
    ("raise_fraction", (0.5, "orbit_at_clearance: raised at this share of the window touching")),
    ("clear_fraction", (0.1, "orbit_at_clearance: cleared below this share")),
    ("revolutions", (4, "orbit_distorted and backward_whirl: revolutions per judged span")),
    ("distortion_raise", (0.1, "orbit_distorted: raised at (backward 1X, 2X, 3X) / forward 1X >= this")),
    ("distortion_clear", (0.05, "orbit_distorted: cleared below this")),
    ("backward_1x_in_distortion", (1, "orbit_distorted: 1 counts the backward 1X as distortion; 0 leaves it out, "
                                      "for supports stiffer one way than the other (an unbalance orbit is then "
                                      "an ellipse: a backward 1X of its own)")),
    ("min_1x_ratio", (0.05, "orbit_distorted: judged only while the forward 1X >= this x C")),
    ("backward_raise", (0.6, "backward_whirl: raised at this share of the power in backward whirl")),
    ("backward_clear", (0.4, "backward_whirl: cleared below this share")),
    ("whirl_orbit_ratio", (0.5, "backward_whirl: ... while the orbit reaches this x C")),
    ("baseline_s", (0.5, "drive_braking: span of the running baselines of torque and speed [s]")),
    ("torque_rise_Nm", (0.005, "drive_braking: raised at a torque rise >= this [N m]")),
    ("torque_clear_fraction", (0.5, "drive_braking: cleared below this x torque_rise_Nm")),
    ("speed_tolerance_rad_per_s", (1e-3, "drive_braking: a speed this far above its baseline vetoes a rise "
                                         "(a commanded acceleration) [rad/s]")),
    ("max_revolution_s", (10.0, "a revolution longer than this is not judged (probe samples kept at most this "
                                "long before a mark) [s]")),
])

CHANNELS = ("orbit_at_clearance", "orbit_distorted", "backward_whirl", "drive_braking")


class ConfigError(ValueError):
    """A design value or a setting the detector cannot work with; the message
    names the key, its value and where it came from."""


def _number(key, value, where):
    if isinstance(value, bool):
        raise ConfigError("%s = %r (%s) is a bool, not a number" % (key, value, where))
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ConfigError("%s = %r (%s) is not a number" % (key, value, where))
    if not math.isfinite(v):
        raise ConfigError("%s = %r (%s) is not a finite number" % (key, value, where))
    return v


class ProbeGeometry(object):
    """The X/Y probe pair: axes at x_angle_rad and y_angle_rad (counter-clockwise
    from +x), sensitivity [V/m]. displacement() inverts the two projections."""

    def __init__(self, x_angle_rad, y_angle_rad, sensitivity_V_per_m):
        self.x_angle_rad = float(x_angle_rad)
        self.y_angle_rad = float(y_angle_rad)
        self.sensitivity = float(sensitivity_V_per_m)
        if not self.sensitivity > 0.0:
            raise ConfigError("probe_sensitivity_V_per_m = %r must be > 0" % sensitivity_V_per_m)
        self.cx, self.sx = math.cos(self.x_angle_rad), math.sin(self.x_angle_rad)
        self.cy, self.sy = math.cos(self.y_angle_rad), math.sin(self.y_angle_rad)
        self.det = self.cx * self.sy - self.sx * self.cy  # sin(y_angle - x_angle)
        if abs(self.det) < 0.1:  # axes closer than 5.7 deg: one direction is barely seen
            raise ConfigError("probe_x_angle_rad = %r and probe_y_angle_rad = %r: the probe axes are %.2f deg apart "
                              "(mod 180); two probes resolve a 2-D displacement only on non-parallel axes "
                              "(|sin(y - x)| >= 0.1)" % (x_angle_rad, y_angle_rad,
                                                          math.degrees(math.asin(min(1.0, abs(self.det))))))

    def displacement(self, x_V, y_V):
        """The rotor centre's displacement (x, y) [m] from the two signals [V]
        (scalars or numpy arrays)."""
        mx, my = x_V / self.sensitivity, y_V / self.sensitivity
        return (mx * self.sy - my * self.sx) / self.det, (self.cx * my - self.cy * mx) / self.det

    def signals(self, x, y):
        """The two signals [V] of a displacement (x, y) [m]: the forward model."""
        return (self.sensitivity * (x * self.cx + y * self.sx), self.sensitivity * (x * self.cy + y * self.sy))


def machine_config(values, where=None):
    """Checks the simulator's design values (dict key -> value for MACHINE_KEYS;
    where: dict key -> where it came from, for the messages) and returns
    (clearance_m, probe_rate_hz, ProbeGeometry). Raises ConfigError naming the
    key, the value and its source."""
    where = where or {}
    v = {}
    for key in MACHINE_KEYS:
        if key not in values:
            raise ConfigError("%s is missing (%s)" % (key, where.get(key, "no value given")))
        v[key] = _number(key, values[key], where.get(key, "given"))
    if v["probe_rate_hz"] <= 0.0:
        raise ConfigError("the simulator's probes are disabled: probe_rate_hz = %g (%s). The monitor judges from the "
                          "proximity probes; set probe_rate_hz > 0 in the simulator's scene (e.g. probe_rate_hz: 2000)"
                          % (v["probe_rate_hz"], where.get("probe_rate_hz", "given")))
    if not v["clearance_m"] > 0.0:
        raise ConfigError("clearance_m = %g (%s) must be > 0" % (v["clearance_m"], where.get("clearance_m", "given")))
    try:
        geometry = ProbeGeometry(v["probe_x_angle_rad"], v["probe_y_angle_rad"], v["probe_sensitivity_V_per_m"])
    except ConfigError as e:
        raise ConfigError("%s (%s)" % (e, ", ".join(where.get(k, "given") for k in
                                                    ("probe_x_angle_rad", "probe_y_angle_rad",
                                                     "probe_sensitivity_V_per_m"))))
    return v["clearance_m"], v["probe_rate_hz"], geometry


def check_settings(settings, probe_rate_hz=None):
    """The detector's settings: defaults with `settings` (dict) applied.
    Unknown names and bad values are ConfigErrors."""
    s = {k: d for k, (d, _) in SETTINGS.items()}
    for k, val in (settings or {}).items():
        if k not in SETTINGS:
            raise ConfigError("unknown setting %r; known: %s" % (k, ", ".join(SETTINGS)))
        s[k] = _number(k, val, "setting")
    positive = ("window_s", "touch_ratio", "raise_fraction", "revolutions", "distortion_raise", "baseline_s",
                "torque_rise_Nm", "whirl_orbit_ratio", "max_revolution_s")
    for k in positive:
        if not s[k] > 0.0:
            raise ConfigError("setting %s = %g must be > 0" % (k, s[k]))
    for lo, hi in (("clear_fraction", "raise_fraction"), ("distortion_clear", "distortion_raise"),
                   ("backward_clear", "backward_raise")):
        if not 0.0 <= s[lo] < s[hi]:
            raise ConfigError("setting %s = %g must be in [0, %s = %g) (hysteresis)" % (lo, s[lo], hi, s[hi]))
    if not 0.0 <= s["torque_clear_fraction"] < 1.0:
        raise ConfigError("setting torque_clear_fraction = %g must be in [0, 1)" % s["torque_clear_fraction"])
    if s["backward_1x_in_distortion"] not in (0.0, 1.0):
        raise ConfigError("setting backward_1x_in_distortion = %g must be 0 or 1" % s["backward_1x_in_distortion"])
    if s["revolutions"] != int(s["revolutions"]):
        raise ConfigError("setting revolutions = %g must be a whole number" % s["revolutions"])
    s["revolutions"] = int(s["revolutions"])
    if probe_rate_hz is not None and probe_rate_hz * s["window_s"] < 10.0:
        raise ConfigError("probe_rate_hz = %g gives %.1f probe samples per window_s = %g s; the orbit_at_clearance "
                          "channel needs at least 10: raise probe_rate_hz to >= %g"
                          % (probe_rate_hz, probe_rate_hz * s["window_s"], s["window_s"], 10.0 / s["window_s"]))
    return s


class Channel(object):
    """One channel's hysteresis: raised on its raise condition, cleared on its
    clear condition; the times are the simulated times of the judged data."""

    def __init__(self, name):
        self.name = name
        self.raised = False
        self.raised_at = float("nan")
        self.first_raised_at = float("nan")
        self.cleared_at = float("nan")

    def update(self, t, raise_now, clear_now):
        if not self.raised and raise_now:
            self.raised, self.raised_at = True, t
            if math.isnan(self.first_raised_at):
                self.first_raised_at = t
        elif self.raised and clear_now:
            self.raised, self.raised_at, self.cleared_at = False, float("nan"), t
        return self.raised


class Revolution(object):
    """What the keyphasor-gated analysis found at one mark (all lengths in m,
    angles in rad, lags in [0, 2 pi): the angle the shaft turns from the mark
    to the probe signal's positive peak)."""

    def __init__(self, **kw):
        self.__dict__.update(kw)


def spin_angles(t, marks):
    """The spin angle at times t (array) from keyphasor marks [(t, speed)]:
    2 pi per mark interval, with the speed varying linearly between two marks
    (constant acceleration), normalised to turn exactly 2 pi. Angle 0 at the
    first mark; NaN outside the marks."""
    phi = np.full(len(t), np.nan)
    for j in range(len(marks) - 1):
        (t0, w0), (t1, w1) = marks[j], marks[j + 1]
        T = t1 - t0
        m = (t >= t0) & (t < t1)
        tau = t[m] - t0
        turned = w0 * T + 0.5 * (w1 - w0) * T  # = (w0 + w1) T / 2
        if turned > 0.0 and w0 >= 0.0 and w1 >= 0.0:
            frac = (w0 * tau + 0.5 * (w1 - w0) / T * tau * tau) / turned
        else:
            frac = tau / T
        phi[m] = 2.0 * math.pi * (j + frac)
    return phi


def cell_weights(phi, span):
    """Quadrature weights of samples at increasing angles phi in [0, span): each
    sample stands for the angles nearer to it than to its neighbours, the
    first from 0, the last to span (they sum to span)."""
    mid = 0.5 * (phi[1:] + phi[:-1])
    edges = np.concatenate(([0.0], mid, [span]))
    return np.diff(edges)


def synchronous(z, phi, span, orders, window=None):
    """Coefficients Z_h of z = sum_h Z_h e^{i h phi} over angles [0, span), by
    quadrature with cell weights (times an optional window)."""
    w = cell_weights(phi, span)
    if window is not None:
        w = w * window
    wsum = np.sum(w)
    return {h: complex(np.sum(w * z * np.exp(-1j * h * phi)) / wsum) for h in orders}


def noise_distortion(z, phi, revolutions, window, orders, fwd, harmonics):
    """The distortion the probes' noise alone would read: the noise's level
    per axis from the second differences of what the synchronous harmonics
    leave of z (the orbit's own curvature removed, which at a few samples per
    revolution would read as noise; 1.4826 x their median absolute value /
    sqrt(6) for white noise; an impact's few samples do not move a median),
    its share of each harmonic's estimate sqrt(sum w^2) / sum w, times
    sqrt(orders), against the forward 1X fwd."""
    rest = z - sum(c * np.exp(1j * h * phi) for h, c in harmonics.items())
    d2 = rest[2:] - 2.0 * rest[1:-1] + rest[:-2]
    if len(d2) == 0 or fwd <= 0:
        return float("inf")
    sigma = 1.4826 * float(np.median(np.abs(np.concatenate((d2.real, d2.imag))))) / math.sqrt(6.0)
    w = cell_weights(phi, 2 * math.pi * revolutions) * window
    per_harmonic = math.sqrt(2.0) * sigma * math.sqrt(float(np.sum(w * w))) / float(np.sum(w))
    return math.sqrt(orders) * per_harmonic / fwd


def full_spectrum(z, dt):
    """(forward power, backward power, power-weighted whirl frequency [Hz]) of
    the complex signal z sampled every dt, mean removed (Hann window)."""
    n = len(z)
    if n < 8:
        return 0.0, 0.0, 0.0
    zc = (z - np.mean(z)) * np.hanning(n)
    p = np.abs(np.fft.fft(zc)) ** 2
    f = np.fft.fftfreq(n, dt)
    keep = np.ones(n, bool)
    keep[0] = False
    if n % 2 == 0:
        keep[n // 2] = False  # the Nyquist bin has no direction
    fwd = float(np.sum(p[keep & (f > 0)]))
    bwd = float(np.sum(p[keep & (f < 0)]))
    tot = fwd + bwd
    return fwd, bwd, (float(np.sum(f[keep] * p[keep]) / tot) if tot > 0 else 0.0)


def _lag(coef):
    return (-math.atan2(coef.imag, coef.real)) % (2.0 * math.pi)


class MachineRubDetector(object):
    """Feed it the probes (feed_probes), the keyphasor (feed_keyphasor) and the
    drive (feed_drive), each stream in time order; read rubbing, reasons(),
    raised_at, first_raised_at, the channels' figures, and last_revolution."""

    def __init__(self, clearance_m, geometry, settings=None, probe_rate_hz=None):
        if not clearance_m > 0.0:
            raise ConfigError("clearance_m = %r must be > 0" % clearance_m)
        self.clearance_m = float(clearance_m)
        self.geometry = geometry
        self.s = check_settings(settings, probe_rate_hz)
        self.channels = collections.OrderedDict((n, Channel(n)) for n in CHANNELS)
        # orbit_at_clearance: (t, |d|, touching) over the window
        self.window = collections.deque()
        self.touching = 0
        self.first_probe_t = None
        self.last_probe_t = -math.inf
        # probe samples (t, x, y) [m] kept for the keyphasor analysis
        self.samples = collections.deque()
        self.marks = []  # [(t, revolution, speed)] in the current run of consecutive revolutions
        self.pending = collections.deque()  # marks not yet judged (no probe sample at or after them yet)
        self.last_revolution = None
        self.revolutions_judged = 0
        # drive_braking: (t, speed, torque) in the window, and in the baseline before it
        self.drive_win = collections.deque()
        self.drive_base = collections.deque()
        self.win_torque = 0.0
        self.rev_torque = collections.deque()  # (t, torque) over the last revolution
        self.rev_torque_sum = 0.0
        self.baseline = LineFit()
        self.drive_t0 = None
        self.torque_rise = 0.0
        self.speed_dip = 0.0
        self.held_torque_baseline = None
        self.last_drive_t = -math.inf

    # ---- the alarm ------------------------------------------------------------
    @property
    def rubbing(self):
        return any(c.raised for c in self.channels.values())

    def reasons(self):
        return [n for n, c in self.channels.items() if c.raised]

    @property
    def raised_at(self):
        """The earliest raise time among the channels raised now (NaN if none)."""
        ts = [c.raised_at for c in self.channels.values() if c.raised]
        return min(ts) if ts else float("nan")

    @property
    def first_raised_at(self):
        """The first time any channel was ever raised (NaN if never)."""
        ts = [c.first_raised_at for c in self.channels.values() if not math.isnan(c.first_raised_at)]
        return min(ts) if ts else float("nan")

    @property
    def cleared_at(self):
        """The latest time a channel cleared (NaN if none has)."""
        ts = [c.cleared_at for c in self.channels.values() if not math.isnan(c.cleared_at)]
        return max(ts) if ts else float("nan")

    # ---- probes: orbit_at_clearance, and the keyphasor's pending marks ----------
    def feed_probes(self, t, x_V, y_V):
        """One probe sample: time [s], the X and Y signals [V]. Returns rubbing."""
        if t <= self.last_probe_t:
            raise ValueError("probe sample at t = %.9g s after one at %.9g s: feed in time order (a new run needs a "
                             "new detector)" % (t, self.last_probe_t))
        self.last_probe_t = t
        if self.first_probe_t is None:
            self.first_probe_t = t
        x, y = self.geometry.displacement(x_V, y_V)
        r = math.hypot(x, y)
        touching = r >= self.s["touch_ratio"] * self.clearance_m
        self.window.append((t, r, touching))
        self.touching += touching
        while self.window and self.window[0][0] <= t - self.s["window_s"]:
            self.touching -= self.window.popleft()[2]
        full = t - self.first_probe_t >= self.s["window_s"] - 1e-12  # judge whole windows only
        share = self.contact_fraction()
        self.channels["orbit_at_clearance"].update(t, full and share >= self.s["raise_fraction"],
                                                   share < self.s["clear_fraction"])
        # Marks judged once the probes have passed them: every sample before the mark is in.
        while self.pending and self.pending[0][0] <= t:
            self._judge_mark(*self.pending.popleft())
        self.samples.append((t, x, y))
        self._trim_samples(t)
        return self.rubbing

    def contact_fraction(self):
        return self.touching / len(self.window) if self.window else 0.0

    def orbit_ratio(self):
        """max |d| / C over the window."""
        return max(w[1] for w in self.window) / self.clearance_m if self.window else 0.0

    def _trim_samples(self, t):
        keep_from = t - self.s["max_revolution_s"]
        if len(self.marks) >= self.s["revolutions"]:
            keep_from = max(keep_from, self.marks[-self.s["revolutions"]][0])
        elif self.marks:
            keep_from = max(keep_from, self.marks[0][0])
        while self.samples and self.samples[0][0] < keep_from:
            self.samples.popleft()

    # ---- keyphasor: 1X, the orbit's distortion, the whirl direction ------------
    def feed_keyphasor(self, t, revolution, speed):
        """One keyphasor mark: time [s], revolution number, speed [rad/s].
        Judged as soon as a probe sample at or after t has been fed."""
        if self.pending and t <= self.pending[-1][0] or self.marks and not self.pending and t <= self.marks[-1][0]:
            raise ValueError("keyphasor mark at t = %.9g s out of order" % t)
        if t < self.last_probe_t:
            self._judge_mark(t, revolution, speed)
        else:
            self.pending.append((t, revolution, speed))
        return self.rubbing

    def _judge_mark(self, t, revolution, speed):
        m = self.marks
        if m and (revolution != m[-1][1] + 1 or t - m[-1][0] > self.s["max_revolution_s"]):
            m.clear()  # a lost mark, or too slow: start a new run of revolutions
        m.append((t, revolution, speed))
        M = self.s["revolutions"]
        if len(m) > M + 1:
            del m[:len(m) - (M + 1)]
        if len(m) < 2:
            return
        ts = np.array([s[0] for s in self.samples])
        if len(ts) == 0:
            return
        xs = np.array([s[1] for s in self.samples])
        ys = np.array([s[2] for s in self.samples])
        z = xs + 1j * ys
        # Per-probe 1X over the last revolution (rectangular, exactly one turn).
        last = [(a[0], a[2]) for a in m[-2:]]
        sel = (ts >= last[0][0]) & (ts < last[1][0])
        if np.count_nonzero(sel) < 8:
            return
        phi1 = spin_angles(ts[sel], last)
        vx, vy = self.geometry.signals(xs[sel], ys[sel])
        cx = 2.0 * synchronous(vx / self.geometry.sensitivity, phi1, 2 * math.pi, (1,))[1]
        cy = 2.0 * synchronous(vy / self.geometry.sensitivity, phi1, 2 * math.pi, (1,))[1]
        rev = Revolution(t=t, revolution=revolution, speed=speed, x_1x_m=abs(cx), x_1x_lag=_lag(cx),
                         y_1x_m=abs(cy), y_1x_lag=_lag(cy), span=0, forward_1x_m=float("nan"),
                         backward_1x_m=float("nan"), distortion=float("nan"), backward_share=float("nan"),
                         whirl_frequency_hz=float("nan"), span_orbit_ratio=float("nan"), judged=False)
        self.last_revolution = rev
        self.revolutions_judged += 1
        if len(m) < M + 1:
            return
        # The span of the last M revolutions: order-tracked, Hann-windowed harmonics.
        span_marks = [(a[0], a[2]) for a in m[-(M + 1):]]
        sel = (ts >= span_marks[0][0]) & (ts < span_marks[-1][0])
        if np.count_nonzero(sel) < 8 * M:
            return
        phi = spin_angles(ts[sel], span_marks)
        zs = z[sel]
        hann = 0.5 - 0.5 * np.cos(phi / M)
        H = synchronous(zs, phi, 2 * math.pi * M, (-3, -2, -1, 0, 1, 2, 3), hann)
        fwd = abs(H[1])
        orders = (-3, -2, -1, 2, 3) if self.s["backward_1x_in_distortion"] else (-3, -2, 2, 3)
        other = math.sqrt(sum(abs(H[h]) ** 2 for h in orders))
        fpow, bpow, wf = full_spectrum(zs, float(np.median(np.diff(ts[sel]))))
        share = bpow / (fpow + bpow) if fpow + bpow > 0 else 0.0
        orbit = float(np.max(np.abs(zs))) / self.clearance_m
        rev.span, rev.forward_1x_m, rev.backward_1x_m = M, fwd, abs(H[-1])
        rev.distortion = other / fwd if fwd > 0 else float("inf")
        rev.backward_share, rev.whirl_frequency_hz, rev.span_orbit_ratio = share, wf, orbit
        rev.judged = (fwd >= self.s["min_1x_ratio"] * self.clearance_m
                      and noise_distortion(zs, phi, M, hann, len(orders), fwd, H) <= 0.5 * self.s["distortion_clear"])
        self.channels["orbit_distorted"].update(
            t, rev.judged and rev.distortion >= self.s["distortion_raise"],
            not rev.judged or rev.distortion < self.s["distortion_clear"])
        self.channels["backward_whirl"].update(
            t, share >= self.s["backward_raise"] and orbit >= self.s["whirl_orbit_ratio"],
            share < self.s["backward_clear"] or orbit < 0.8 * self.s["whirl_orbit_ratio"])

    def whirl_direction(self):
        """+1 forward, -1 backward (the full spectrum's dominant side over the
        last judged span), 0 before the first."""
        r = self.last_revolution
        if r is None or math.isnan(r.backward_share):
            return 0
        return -1 if r.backward_share > 0.5 else 1

    # ---- drive: torque rise, speed dip ----------------------------------------
    def feed_drive(self, t, speed, torque):
        """One drive sample: time [s], speed [rad/s], drive torque [N m]."""
        if t <= self.last_drive_t:
            raise ValueError("drive sample at t = %.9g s after one at %.9g s: feed in time order"
                             % (t, self.last_drive_t))
        self.last_drive_t = t
        w, b = self.s["window_s"], self.s["baseline_s"]
        if self.drive_t0 is None:
            self.drive_t0 = t
        # The torque over the last revolution: no once-per-revolution part.
        rev = self.rev_torque
        rev.append((t, float(torque)))
        self.rev_torque_sum += float(torque)
        period = min(2 * math.pi / speed, self.s["max_revolution_s"]) if speed > 0 else w
        while len(rev) > 1 and rev[0][0] <= t - period:
            self.rev_torque_sum -= rev.popleft()[1]
        torque = self.rev_torque_sum / len(rev)
        self.drive_win.append((t, float(speed), torque))
        self.win_torque += torque
        while self.drive_win and self.drive_win[0][0] <= t - w:  # from the window into the baseline
            old = self.drive_win.popleft()
            self.win_torque -= old[2]
            self.drive_base.append(old)
            self.baseline.add(old)
        while self.drive_base and self.drive_base[0][0] <= t - w - b:
            self.baseline.remove(self.drive_base.popleft())
        if t - self.baseline.t_ref > 1.0:  # re-sum now and then: no drift of the running sums
            self.baseline.rebase(t, self.drive_base)
        ch = self.channels["drive_braking"]
        if t - self.drive_t0 < w + 0.5 * b or self.baseline.n < 3:  # less than half a baseline yet: no verdict
            return self.rubbing
        t_mid = sum(s[0] for s in self.drive_win) / len(self.drive_win)
        speed_base, _ = self.baseline.value_at(t)
        _, torque_line = self.baseline.value_at(t_mid)
        # The line, or where that is higher the lowest torque of the baseline's
        # last two revolutions: after the torque steps down (a run-up reaching
        # its target speed, a rub's friction ending) the line fitted across the
        # step undershoots the new level, and the level would read as a rise
        # (test_machine_rub_detector.py, test_a_torque_step_down_does_not_raise);
        # a step up the window holds is not yet in those revolutions, and a
        # torque drifting down has its lowest there.
        recent = self.drive_base[-1][2]
        for smp in reversed(self.drive_base):
            if smp[0] <= t - w - 2.0 * period:
                break
            recent = min(recent, smp[2])
        torque_base = max(torque_line, recent)
        self.speed_dip = speed_base - float(speed)
        baseline = self.held_torque_baseline if ch.raised else torque_base
        self.torque_rise = self.win_torque / len(self.drive_win) - baseline
        commanded = -self.speed_dip > self.s["speed_tolerance_rad_per_s"]
        was = ch.raised
        ch.update(t, self.torque_rise >= self.s["torque_rise_Nm"] and not commanded,
                  self.torque_rise < self.s["torque_clear_fraction"] * self.s["torque_rise_Nm"])
        if ch.raised and not was:
            self.held_torque_baseline = baseline
        elif not ch.raised:
            self.held_torque_baseline = None
        return self.rubbing


class LineFit(object):
    """Least-squares straight lines of speed and torque against time over a
    changing set of samples (t, speed, torque), by running sums; times
    relative to t_ref, which rebase() moves (and re-sums)."""

    def __init__(self):
        self.t_ref = 0.0
        self.rebase(0.0, ())

    def rebase(self, t_ref, samples):
        self.t_ref = t_ref
        self.n = 0
        self.s1 = self.s2 = 0.0
        self.sy = [0.0, 0.0]
        self.sty = [0.0, 0.0]
        for smp in samples:
            self.add(smp)

    def _apply(self, smp, sign):
        tau = smp[0] - self.t_ref
        self.n += sign
        self.s1 += sign * tau
        self.s2 += sign * tau * tau
        for i in (0, 1):
            self.sy[i] += sign * smp[1 + i]
            self.sty[i] += sign * tau * smp[1 + i]

    def add(self, smp):
        self._apply(smp, 1)

    def remove(self, smp):
        self._apply(smp, -1)

    def value_at(self, t):
        """(speed, torque) of the fitted lines at time t."""
        tau = t - self.t_ref
        den = self.n * self.s2 - self.s1 * self.s1
        out = []
        for i in (0, 1):
            slope = (self.n * self.sty[i] - self.s1 * self.sy[i]) / den if den > 0 else 0.0
            out.append((self.sy[i] - slope * self.s1) / self.n + slope * tau)
        return tuple(out)


# ---- offline: the detector on the headless runner's output -------------------------
def read_csv_columns(path, need):
    with open(path) as f:
        r = csv.DictReader(f)
        if not r.fieldnames or any(k not in r.fieldnames for k in need):
            raise ValueError("%s lacks columns %s (has %s)" % (path, ", ".join(k for k in need if k not in
                                                                                (r.fieldnames or [])),
                                                              ", ".join(r.fieldnames or [])))
        rows = [[float(row[k]) for k in need] for row in r]
    return np.array(rows).reshape(-1, len(need))


def replay(summary, probes_csv, keyphasor_csv, run_csv=None, settings=None):
    """Feeds the detector with a rotor_rub_run's outputs in simulated-time
    order; the design data from its JSON summary (scene_values). Returns
    (detector, transitions [(t, rubbing, reasons)])."""
    values = summary["scene_values"]
    clearance, rate, geometry = machine_config({k: values.get(k) for k in MACHINE_KEYS},
                                               {k: "the summary's scene_values" for k in MACHINE_KEYS})
    det = MachineRubDetector(clearance, geometry, settings, rate)
    p = read_csv_columns(probes_csv, ["t", "x_V", "y_V"])
    k = read_csv_columns(keyphasor_csv, ["t", "revolution", "speed"])
    streams = [(row[0], 0, row) for row in p] + [(row[0], 1, row) for row in k]
    if run_csv:
        with open(run_csv) as f:
            cols = next(csv.reader(f))
        need = ["t", "speed"] + (["drive_torque"] if "drive_torque" in cols else [])
        for row in read_csv_columns(run_csv, need):
            streams.append((row[0], 2, row if len(row) == 3 else np.array([row[0], row[1], 0.0])))
    streams.sort(key=lambda s: (s[0], s[1]))
    transitions, was = [], False
    for t, kind, row in streams:
        if kind == 0:
            det.feed_probes(row[0], row[1], row[2])
        elif kind == 1:
            det.feed_keyphasor(row[0], int(row[1]), row[2])
        else:
            det.feed_drive(row[0], row[1], row[2])
        if det.rubbing != was:
            was = det.rubbing
            transitions.append((t, was, det.reasons()))
    return det, transitions


def main(argv=None):
    ap = argparse.ArgumentParser(description="The machine rub detector on a rotor_rub_run's outputs (offline): "
                                 "prints when the alarm is raised and cleared, and the delay after the first contact.")
    ap.add_argument("summary", help="the run's --summary JSON (design data: clearance, probe angles, sensitivity; "
                    "ground truth: first_contact_s)")
    ap.add_argument("--probes", required=True, help="the run's --probes CSV")
    ap.add_argument("--keyphasor", required=True, help="the run's --keyphasor CSV")
    ap.add_argument("--csv", help="the run's --csv (speed, and drive_torque when it has the column)")
    ap.add_argument("--set", action="append", default=[], metavar="NAME=VALUE", help="a detector setting")
    a = ap.parse_args(argv)
    try:
        settings = dict(kv.split("=", 1) for kv in a.set)
        with open(a.summary) as f:
            summary = json.load(f)
        det, transitions = replay(summary, a.probes, a.keyphasor, a.csv, settings)
    except (ValueError, OSError, KeyError) as e:
        print("machine_rub_detector: %s" % e, file=sys.stderr)
        return 2
    for t, on, why in transitions:
        print("%.4f s  %s  %s" % (t, "raised" if on else "cleared", ",".join(why)))
    first = summary.get("first_contact_s")
    print("first contact %s s, first alarm %s s, detection delay %s s" % (
        "none" if first is None else "%.4f" % first, "%.4f" % det.first_raised_at,
        "%.4f" % (det.first_raised_at - first) if first is not None else "n/a"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
