// The unit vectors (cos, sin) of two angles in one call, for the contact
// regime's derivative, which needs both the contact angle psi's and the
// spin angle phi's: on glibc's libmvec (x86-64), the 2-lane SSE2 sin and
// cos, where two scalar sincos calls cost about twice as much (15-20 ns
// against 26-37 ns for a pair, a loop of 2^22 pairs on the 2-core CI
// machine; the sincos calls were 30 % of a switching run, perf). libmvec's
// error is at most 4 ulp (glibc's manual), libm's 1: 9e-16 relative, far
// below any tolerance. Without libmvec, two std::cos/std::sin pairs.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <limits>

namespace rotor_rub::core {

// ua = (cos a, sin a), ub = (cos b, sin b).
void unit_vectors(double a, double b, Eigen::Vector2d& ua, Eigen::Vector2d& ub);

// The unit vectors of angles known ahead (a prescribed drive's spin angle at
// an integrator attempt's stage times: the unbalance's forcing depends on
// time alone), taken two per call, then looked up by the angle; one more
// angle kept (a step end's). Any other angle's by std::cos, std::sin. The
// same angle gets the same bits while it stays prepared or kept.
template <int N>
class PreparedUnitVectors {
 public:
  void prepare(const std::array<double, N>& angles_rad) {
    angle_rad_ = angles_rad;
    for (int i = 0; i + 1 < N; i += 2) unit_vectors(angle_rad_[i], angle_rad_[i + 1], unit_[i], unit_[i + 1]);
    if constexpr (N % 2 == 1) {
      Eigen::Vector2d unused;
      unit_vectors(angle_rad_[N - 1], 0.0, unit_[N - 1], unused);
    }
    prepared_ = N;
    next_ = 0;
  }
  void keep(double angle_rad, const Eigen::Vector2d& unit) {
    kept_angle_rad_ = angle_rad;
    kept_unit_ = unit;
  }
  // (cos a, sin a); the prepared angles are usually asked for in order.
  Eigen::Vector2d at(double angle_rad) {
    if (next_ < prepared_ && angle_rad_[next_] == angle_rad) return unit_[next_++];
    for (int i = 0; i < prepared_; ++i) {
      if (angle_rad_[i] == angle_rad) return unit_[i];
    }
    if (angle_rad == kept_angle_rad_) return kept_unit_;
    return Eigen::Vector2d(std::cos(angle_rad), std::sin(angle_rad));
  }

 private:
  std::array<double, N> angle_rad_{};
  std::array<Eigen::Vector2d, N> unit_{};
  int prepared_ = 0, next_ = 0;
  double kept_angle_rad_ = std::numeric_limits<double>::quiet_NaN();
  Eigen::Vector2d kept_unit_ = Eigen::Vector2d::UnitX();
};

}  // namespace rotor_rub::core
