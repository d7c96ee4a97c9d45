// The drive: spin angle, speed and angular acceleration against time, as
// segments of constant angular acceleration. With the prescribed drive
// (drive_model prescribed) this is the spin: friction torque does not slow
// the rotor. With a motor (drive_model motor) it is the speed controller's
// reference (model.hpp). A speed command appends a segment. Segment boundaries are discontinuities of the unbalance
// force's tangential term, so integration restarts at each of them.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

struct DriveState {
  double angle_rad = 0.0;         // phi: spin angle of the mass-centre offset
  double speed_rad_per_s = 0.0;   // omega = dphi/dt (counter-clockwise positive)
  double accel_rad_per_s2 = 0.0;  // alpha = domega/dt (a motor drive: the reference's until the forces are known)
  double motor_torque_N_m = 0.0;  // a motor drive only: the motor's torque T_m on the rotor
};

// One segment: constant acceleration from start_time_s. Evaluated without
// clamping so that an integrator step may probe slightly past its end.
struct SpeedSegment {
  double start_time_s = 0.0;
  double start_angle_rad = 0.0;
  double start_speed_rad_per_s = 0.0;
  double accel_rad_per_s2 = 0.0;

  DriveState at(double t_s) const {
    const double tau = t_s - start_time_s;
    return {start_angle_rad + start_speed_rad_per_s * tau + 0.5 * accel_rad_per_s2 * tau * tau,
            start_speed_rad_per_s + accel_rad_per_s2 * tau, accel_rad_per_s2};
  }
};

class SpeedProfile {
 public:
  explicit SpeedProfile(const SpeedProfileParameters& p);

  // Ramps from the speed at t_s to target at |accel| (the sign follows the
  // direction of the change) and then holds it. Drops segments after t_s.
  // Throws std::invalid_argument when t_s is before the current segment start.
  void command(double t_s, double target_rad_per_s, double accel_magnitude_rad_per_s2);

  DriveState at(double t_s) const { return segment_at(t_s).at(t_s); }
  const SpeedSegment& segment_at(double t_s) const;
  // The first segment start strictly after t_s (infinity if none).
  double next_break_after(double t_s) const;
  // The first time at or after t_s at which the spin angle equals angle_rad
  // (not modulo 2 pi), in closed form on the segments; infinity if the drive
  // never gets there (it stops short, or stands still). The speed is never
  // negative, so the angle never decreases.
  double time_at_angle(double t_s, double angle_rad) const;
  const std::vector<SpeedSegment>& segments() const { return segments_; }

 private:
  void append_ramp(double t_s, const DriveState& from, double target, double accel_magnitude);
  std::vector<SpeedSegment> segments_;
};

}  // namespace rotor_rub::core
