// The unit vectors (cos, sin) of two angles in one call, for the contact
// regime's derivative, which needs both the contact angle psi's and the
// spin angle phi's: on glibc's libmvec (x86-64), the 2-lane SSE2 sin and
// cos, about the cost of one scalar sincos (docs/benchmarks.md, the hot
// path). libmvec's
// error is at most 4 ulp (glibc's manual), libm's 1: 9e-16 relative, far
// below any tolerance. Without libmvec, two std::cos/std::sin pairs.
#pragma once

#include <Eigen/Core>

namespace rotor_rub::core {

// ua = (cos a, sin a), ub = (cos b, sin b).
void unit_vectors(double a, double b, Eigen::Vector2d& ua, Eigen::Vector2d& ub);

}  // namespace rotor_rub::core
