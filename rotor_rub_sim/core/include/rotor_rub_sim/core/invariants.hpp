// What every accepted step must hold, whatever the method: checked by the
// simulation loop at the end of every accepted step and at every delivered
// sample, so that a defect (a missed event, a wrong friction direction, a
// NaN) fails the run as invariant_violated instead of ending `ok`.
//
// * Finiteness of every field of the sample.
// * Non-penetration (rigid methods only; penetration is the penalty method's
//   model): delta - C <= penetration_tolerance_m. The event state, the
//   projected state and the dense output carry the integrator's error, of
//   order atol + rtol |x| per position component (|x| <= C near the bore);
//   kPenetrationSafety covers the dense output's error, an order above the
//   step's own local error estimate. A located touchdown lies on the far
//   side of the bore by up to event_time_resolution_s (run_types.hpp), where
//   the rotor has moved into the bore by up to its approach speed times that,
//   which |v_r - v_s| bounds: penetration_limit_m(). At the tightest
//   tolerances that time resolution is the larger part (rtol 1e-12, C 2 mm:
//   3e-14 m, against 1.2e-13 m at 1.2 m/s; such a run at 1500 rad/s failed
//   at 3.4e-14 m before this term).
// * Friction cone: |F_t| <= f F_n (to rounding).
// * Dissipative friction: F_t v_slide <= 0 (friction never drives the
//   sliding) once |v_slide| exceeds sliding_tolerance_m_per_s, the velocity
//   error of the same integrator (a located reversal leaves a residual of that
//   size).
#pragma once

#include <cmath>
#include <cstdio>
#include <limits>

#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

inline constexpr double kPenetrationSafety = 10.0;
// Relative rounding allowance of the friction cone check: F_t = f F_n is
// computed in a different order of operations than f F_n itself.
inline constexpr double kConeRounding = 1e-9;

struct InvariantLimits {
  bool check_penetration = true;
  double penetration_tolerance_m = 0.0;
  double sliding_tolerance_m_per_s = 0.0;
  double friction_coefficient = 0.0;

  /// The largest delta - C a sample may show [m]: the integrator's part and
  /// the located events' time resolution at the sample's relative speed.
  double penetration_limit_m(const Sample& s) const {
    return penetration_tolerance_m + (s.kin.rotor_vel - s.kin.stator_vel).norm() * event_time_resolution_s(s.t_s);
  }

  static InvariantLimits for_scene(const Scene& scene) { return for_scene(scene, scene.model.rotor_radius_m); }
  // rotor_radius_m: the radius the rotor slides at (a flexible rotor's rub
  // station's: contact_radius_of()).
  static InvariantLimits for_scene(const Scene& scene, double rotor_radius_m) {
    InvariantLimits l;
    const double atol = scene.solver.atol, rtol = scene.solver.rtol;
    l.check_penetration = scene.solver.method != Method::kPenalty;
    l.penetration_tolerance_m = kPenetrationSafety * (atol + rtol * scene.model.clearance_m);
    const double surface_speed = scene.speed.max_speed_rad_per_s * rotor_radius_m;
    l.sliding_tolerance_m_per_s = kPenetrationSafety * (atol + rtol * surface_speed);
    if (scene.solver.method == Method::kPenalty) {
      // The penalty method's friction is regularised (a tangential damper
      // capped at f F_n): it never drives the sliding, no tolerance needed
      // beyond rounding.
      l.sliding_tolerance_m_per_s = 0.0;
    }
    l.friction_coefficient = scene.model.friction_coefficient;
    return l;
  }
};

// Throws MethodFailure(kInvariantViolated) naming the invariant, the value
// and the limit.
inline void check_invariants(const Sample& s, const InvariantLimits& l) {
  auto fail = [&](const char* what, double value, double limit) {
    char msg[240];
    // The failure carries the time; the runner and the node print it.
    std::snprintf(msg, sizeof msg, "invariant violated: %s (%.6g, limit %.6g)", what, value, limit);
    throw MethodFailure(FailureClass::kInvariantViolated, s.t_s, msg);
  };
  const bool finite = s.kin.rotor_pos.allFinite() && s.kin.rotor_vel.allFinite() && s.kin.stator_pos.allFinite() &&
                      s.kin.stator_vel.allFinite() && std::isfinite(s.normal_force_N) &&
                      std::isfinite(s.friction_force_N) && std::isfinite(s.drive.speed_rad_per_s) &&
                      std::isfinite(s.drive.angle_rad) && std::isfinite(s.drive_torque_N_m) &&
                      std::isfinite(s.friction_torque_N_m) && s.probe_displacement_m.allFinite();
  if (!finite) fail("non-finite state or force", std::numeric_limits<double>::quiet_NaN(), 0.0);
  // The limit's time-resolution term only ever adds: checked past the
  // tolerance alone, as nearly every sample is well inside it.
  if (l.check_penetration && s.penetration_m > l.penetration_tolerance_m &&
      s.penetration_m > l.penetration_limit_m(s)) {
    fail("rotor beyond the clearance: delta - C [m]", s.penetration_m, l.penetration_limit_m(s));
  }
  if (s.normal_force_N < 0.0) fail("negative normal force [N]", s.normal_force_N, 0.0);
  const double cone = l.friction_coefficient * s.normal_force_N;
  if (std::abs(s.friction_force_N) > cone * (1.0 + kConeRounding) + 1e-300) {
    fail("friction outside the cone: |F_t| [N]", std::abs(s.friction_force_N), cone);
  }
  if (s.friction_force_N * s.sliding_velocity_m_per_s > 0.0 &&
      std::abs(s.sliding_velocity_m_per_s) > l.sliding_tolerance_m_per_s) {
    fail("friction drives the sliding: v_slide [m/s] with F_t along it", s.sliding_velocity_m_per_s,
         l.sliding_tolerance_m_per_s);
  }
}

}  // namespace rotor_rub::core
