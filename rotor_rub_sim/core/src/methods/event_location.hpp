// Event location on dense output: Boost.Odeint has none, so a method checks an
// event function at the ends of each accepted step and, on a sign change,
// finds the root inside the step with TOMS 748 on the interpolant.
#pragma once

#include <algorithm>
#include <boost/math/tools/roots.hpp>
#include <cstdint>
#include <limits>

#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

// The earliest root of f in [t0, t1] given f(t0) and f(t1) of opposite sign
// (or f(t1) == 0). Returns the end of the bracket on the far side of the
// sign change, so the event state is guaranteed past the switching surface.
template <class F>
double locate_event(F&& f, double t0, double f0, double t1, double f1, RunStats& stats) {
  if (f1 == 0.0) return t1;
  std::uintmax_t max_iter = 200;
  auto tol = [](double a, double b) {
    return std::abs(b - a) <= event_time_resolution_s(std::max(std::abs(a), std::abs(b)));
  };
  const auto bracket = boost::math::tools::toms748_solve(f, t0, t1, f0, f1, tol, max_iter);
  stats.root_iterations += static_cast<long>(max_iter);
  return bracket.second;
}

// A crossing of g between two points a < b where g is below zero at both
// (ga, gb < 0): g rising through zero and back between them, at one
// interior maximum (a graze shorter than the points' spacing). The maximum
// is where g's rate falls through zero, the rate a difference quotient of
// step h_s on the dense output (for functions with no rate in closed form),
// and g there decides. Returns the first root in [a, t_max] (on the far
// side, as locate_event), or +infinity when g does not rise at a and fall
// at b, or stays below zero.
template <class G>
double locate_interior_crossing(G&& g, double a, double ga, double b, double gb, double h_s, RunStats& stats) {
  constexpr double kNone = std::numeric_limits<double>::infinity();
  // A step below a few ulps of t differences rounding, not g: too short an
  // interval to hold a graze of interest.
  if (!(h_s > 8.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(a), std::abs(b)))) return kNone;
  const double rate_a = (g(a + h_s) - ga) / h_s;
  if (!(rate_a > 0.0)) return kNone;
  const double rate_b = (gb - g(b - h_s)) / h_s;
  if (!(rate_b < 0.0)) return kNone;
  auto falling_rate = [&g, a, b, h_s](double t) {
    const double lo = std::max(t - h_s, a), hi = std::min(t + h_s, b);
    return (g(lo) - g(hi)) / (hi - lo);
  };
  const double t_max = locate_event(falling_rate, a, -rate_a, b, -rate_b, stats);
  const double g_max = g(t_max);
  if (g_max < 0.0) return kNone;
  return locate_event(g, a, ga, t_max, g_max, stats);
}

}  // namespace rotor_rub::core
