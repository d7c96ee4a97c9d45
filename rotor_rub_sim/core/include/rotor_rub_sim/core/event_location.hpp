// Event location on dense output: Boost.Odeint has none, so a method checks an
// event function at the ends of each accepted step and, on a sign change,
// finds the root inside the step with TOMS 748 on the interpolant.
#pragma once

#include <boost/math/tools/roots.hpp>
#include <cstdint>

#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

// Time resolution of located events [s]: far below any step of interest,
// yet representable beside t ~ 1e3 s.
inline constexpr double kEventTimeTolerance_s = 1e-13;

// The earliest root of f in [t0, t1] given f(t0) and f(t1) of opposite sign
// (or f(t1) == 0). Returns the end of the bracket on the far side of the
// sign change, so the event state is guaranteed past the switching surface.
template <class F>
double locate_event(F&& f, double t0, double f0, double t1, double f1, RunStats& stats) {
  if (f1 == 0.0) return t1;
  std::uintmax_t max_iter = 200;
  auto tol = [](double a, double b) { return std::abs(b - a) <= kEventTimeTolerance_s; };
  const auto bracket = boost::math::tools::toms748_solve(f, t0, t1, f0, f1, tol, max_iter);
  stats.root_iterations += static_cast<long>(max_iter);
  return bracket.second;
}

}  // namespace rotor_rub::core
