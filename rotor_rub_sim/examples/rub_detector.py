"""The run-up controller's rub detector (no ROS here), on the simulator's
exact state: the rotor's displacement relative to the stator, d = r_r - r_s,
which no machine measures as such (its probes sit on the casing and see r_r;
machine_rub_detector.py is the rub monitor's detector, on what a machine
offers). The controller keeps this one because it must decide in lockstep
with the simulator, whose lockstep contract orders the `state` topic only.

Sustained rub: over a sliding window (default 20 ms of simulated time), at
least `raise_fraction` of the samples have |d| >= `touch_ratio` * clearance;
the alarm clears when that share falls below `clear_fraction` (hysteresis).
The whirl frequency (the mean rate of change of d's angle over the window)
is reported beside the spin frequency: rub-induced backward whirl shows as a
negative whirl frequency while the rotor spins forward.

Deterministic: the verdict after a sample depends only on the samples fed so
far, in order, so the controller can run it in lockstep."""
import collections
import math


def clearance_of(rx, ry, sx, sy, penetration):
    """The scene's clearance C [m] from one simulator state: its penetration is
    |r_r - r_s| - C. A value the scene owns comes from the simulator, never a
    second parameter that may disagree with it."""
    return math.hypot(rx - sx, ry - sy) - penetration


class RubDetector(object):
    def __init__(self, clearance_m, window_s=0.02, touch_ratio=0.995, raise_fraction=0.5, clear_fraction=0.1):
        self.clearance_m = clearance_m
        self.window_s = window_s
        self.touch_ratio = touch_ratio
        self.raise_fraction = raise_fraction
        self.clear_fraction = clear_fraction
        self.samples = collections.deque()  # (t, |d|, angle of d, touching)
        self.touching = 0
        self.rubbing = False
        self.raised_at = float("nan")
        self.first_raised_at = float("nan")

    def feed(self, t, rx, ry, sx, sy):
        """One sample: time [s], rotor and stator positions [m]. Returns rubbing."""
        dx, dy = rx - sx, ry - sy
        r = math.hypot(dx, dy)
        touching = r >= self.touch_ratio * self.clearance_m
        self.samples.append((t, r, math.atan2(dy, dx), touching))
        self.touching += touching
        while self.samples and self.samples[0][0] < t - self.window_s:
            self.touching -= self.samples.popleft()[3]
        full = t >= self.window_s - 1e-12  # judge whole windows only
        share = self.contact_fraction()
        if not self.rubbing and full and share >= self.raise_fraction:
            self.rubbing = True
            self.raised_at = t
            if math.isnan(self.first_raised_at):
                self.first_raised_at = t
        elif self.rubbing and share < self.clear_fraction:
            self.rubbing = False
            self.raised_at = float("nan")
        return self.rubbing

    def contact_fraction(self):
        return self.touching / len(self.samples) if self.samples else 0.0

    def orbit_ratio(self):
        return max(s[1] for s in self.samples) / self.clearance_m if self.samples else 0.0

    def whirl_frequency_hz(self):
        """Mean d(angle)/dt over the window, unwrapped [Hz]."""
        if len(self.samples) < 2:
            return 0.0
        total = 0.0
        prev = self.samples[0][2]
        for s in list(self.samples)[1:]:
            step = s[2] - prev
            step -= 2 * math.pi * round(step / (2 * math.pi))
            total += step
            prev = s[2]
        span = self.samples[-1][0] - self.samples[0][0]
        return total / (2 * math.pi * span) if span > 0 else 0.0
