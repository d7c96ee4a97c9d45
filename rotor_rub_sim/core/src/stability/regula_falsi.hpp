// The root of a function along a continuation step, where its sign differs
// at the step's two ends (the continuations' folds, stability changes and
// bifurcations: full_rub_continuation.cpp, orbit_continuation.cpp).
#pragma once

#include <cmath>
#include <functional>

namespace rotor_rub::core {

// The root of phi in (0, s1) by regula falsi with the Illinois rule, phi(0)
// = phi0 and phi(s1) = phi1 of opposite signs, to a bracket of fraction
// of s1.
inline double regula_falsi(const std::function<double(double)>& phi, double phi0, double s1, double phi1,
                           double fraction) {
  double a = 0.0, fa = phi0, b = s1, fb = phi1;
  int side = 0;
  for (int it = 0; it < 100 && b - a > fraction * s1; ++it) {
    const double c = b - fb * (b - a) / (fb - fa);
    const double fc = phi(c);
    if (fc == 0.0) return c;
    if ((fc < 0.0) == (fb < 0.0)) {
      b = c;
      fb = fc;
      if (side == -1) fa *= 0.5;
      side = -1;
    } else {
      a = c;
      fa = fc;
      if (side == 1) fb *= 0.5;
      side = 1;
    }
  }
  return std::abs(fa) < std::abs(fb) ? a : b;
}

}  // namespace rotor_rub::core
