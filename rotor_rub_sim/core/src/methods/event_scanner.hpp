// The scan of an accepted step for events, shared by the three methods, the
// CVODE contender and the periodic orbits' shooting: an event function g is
// an event where it rises through zero; each checks its functions at scan
// points spread evenly over the step and finds a crossing between two of
// them with crossing() (on the step's dense output: event_location.hpp).
#pragma once

#include <cmath>
#include <limits>

#include "methods/event_location.hpp"
#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

// Points per step where the event functions are checked (the last at the
// step's end): two on dopri5, rosenbrock4 and rk4, whose short steps leave at
// most one extremum of the gap between two points (the gap's rate locates a
// graze there: ShallowGraze.ContactShorterThanAStepIsFelt), four on rkf78
// and dop853, whose steps turn the spin by up to about 3 rad.
constexpr int scan_points(Integrator integrator) {
  return integrator == Integrator::kDop853 || integrator == Integrator::kRkf78 ? 4 : 2;
}

// The i-th of n scan points of [t0, t1], i in 1..n: the n-th is t1 exactly.
inline double scan_point(double t0, double t1, int i, int n) { return i == n ? t1 : t0 + (t1 - t0) * i / n; }

// A held contact's event functions (the normal force, the stick force
// against the cone) carry the unbalance at its angle in the contact frame,
// phi - psi, which the state need not see: rolling on a rigid stator holds
// psi'' = -A R_r / C, a parabola whose error estimate is zero, and the error
// control would step over whole revolutions of that angle (and restart the
// next regime with such a step). A held step turns that angle by at most
// this much per scan interval, so that an interval holds at most one
// extremum of the forces' first harmonic and the rates at its ends find it
// (test/core/test_transitions.cpp).
inline constexpr double kMaxScanAngle_rad = 0.25 * 3.14159265358979323846;

// The difference step of a crossing and back without rates in closed form
// (locate_interior_crossing), per interval b - a: small against a force's
// variation between two scan points, large against its rounding.
inline constexpr double kInteriorRateStep = 1e-4;

// A function that starts its regime within this time of its surface, at a
// rate into its own side, starts on it (a rebound, a slip from rest): its
// crossing right after the start is found by the deflated bracket g(t) /
// (t - t_start), which is sound only there (elsewhere singular at t_start).
inline constexpr double kOnSurface_s = 10.0 * kEventTimeTolerance_s;
inline bool starts_on_surface(double value, double rate) {
  return rate < 0.0 && std::abs(value) <= -rate * kOnSurface_s;
}

// What a scan knows of one event function at an interval [a, b].
struct EventWatch {
  // Seen strictly below zero since its regime began: a sign change counts.
  bool armed = false;
  // Where its regime began, and how it began there (when not armed).
  double regime_start_s = std::numeric_limits<double>::quiet_NaN();
  bool on_surface = false;  // on its surface with start_rate < 0 into its side
  double start_rate = 0.0;
  // On its surface with no rate (a slip begun at a breakaway: the slip force
  // equals the stick force there, v_slide' = 0), departing quadratically.
  bool on_surface_without_rate = false;
  // Looked for: a crossing and back between two points where it is below
  // zero at both (a graze of the bore, a lift-off that dips out and back).
  bool interior = true;
};

// The crossing of g in [a, b], or +infinity: a sign change of an armed
// function; right after the regime's start, the deflated function g(t) /
// (t - t_start), whose value at the start is the start's rate, so the
// crossing is bracketed however short the excursion; an unrated start probed
// at points nearer it (TransitionSweep, test_transitions.cpp); a
// crossing and back between a and b, by g's maximum between them, where its
// rate falls through zero (rate(t) in closed form, rate_a and rate_b its
// values at a and b; NaN for none: a difference quotient on the dense
// output), and g there decides. The far end of the bracket, as locate_event.
template <class G, class Rate>
double crossing(const EventWatch& w, G&& g, Rate&& rate, double a, double ga, double rate_a, double b, double gb,
                double rate_b, RunStats& stats) {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  if (w.armed && ga < 0.0 && gb >= 0.0) return locate_event(g, a, ga, b, gb, stats);
  const bool from_start = !w.armed && a == w.regime_start_s && gb >= 0.0;
  if (from_start && w.on_surface_without_rate) {
    for (const double fraction : {1e-3, 1e-2, 1e-1, 0.5}) {
      const double t = a + fraction * (b - a), gt = g(t);
      if (gt < 0.0) return locate_event(g, t, gt, b, gb, stats);
    }
    return kNone;
  }
  if (from_start && w.on_surface) {
    const double t_start = w.regime_start_s;
    auto deflated = [&g, t_start](double t) { return g(t) / (t - t_start); };
    return locate_event(deflated, a, w.start_rate, b, gb / (b - a), stats);
  }
  if (!(w.interior && w.armed && ga < 0.0 && gb < 0.0)) return kNone;
  if (std::isnan(rate_a) || std::isnan(rate_b)) {
    return locate_interior_crossing(g, a, ga, b, gb, kInteriorRateStep * (b - a), stats);
  }
  if (rate_a > 0.0 && rate_b < 0.0) {
    auto falling_rate = [&rate](double t) { return -rate(t); };
    const double tm = locate_event(falling_rate, a, -rate_a, b, -rate_b, stats);
    const double gm = g(tm);
    if (gm >= 0.0) return locate_event(g, a, ga, tm, gm, stats);
  }
  return kNone;
}

// crossing() for a function with no rate in closed form.
template <class G>
double crossing(const EventWatch& w, G&& g, double a, double ga, double b, double gb, RunStats& stats) {
  const double no_rate = std::numeric_limits<double>::quiet_NaN();
  auto rate = [](double) { return std::numeric_limits<double>::quiet_NaN(); };
  return crossing(w, g, rate, a, ga, no_rate, b, gb, no_rate, stats);
}

}  // namespace rotor_rub::core
