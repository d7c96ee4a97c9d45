#include "rotor_rub_sim/core/speed_profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rotor_rub::core {

SpeedProfile::SpeedProfile(const SpeedProfileParameters& p) {
  const DriveState start{p.initial_angle_rad, p.initial_speed_rad_per_s, 0.0};
  append_ramp(0.0, start, p.target_speed_rad_per_s, p.acceleration_rad_per_s2);
}

void SpeedProfile::append_ramp(double t_s, const DriveState& from, double target, double accel_magnitude) {
  const double delta = target - from.speed_rad_per_s;
  if (delta != 0.0 && accel_magnitude > 0.0) {
    const double accel = std::copysign(accel_magnitude, delta);
    segments_.push_back({t_s, from.angle_rad, from.speed_rad_per_s, accel});
    const double t_reach = t_s + delta / accel;
    const DriveState reached = segments_.back().at(t_reach);
    segments_.push_back({t_reach, reached.angle_rad, target, 0.0});
  } else {
    segments_.push_back({t_s, from.angle_rad, from.speed_rad_per_s, 0.0});
  }
}

void SpeedProfile::command(double t_s, double target_rad_per_s, double accel_magnitude_rad_per_s2) {
  if (!segments_.empty() && t_s < segments_.front().start_time_s) {
    throw std::invalid_argument("speed command time precedes the profile start");
  }
  const DriveState now = at(t_s);
  while (!segments_.empty() && segments_.back().start_time_s >= t_s) segments_.pop_back();
  append_ramp(t_s, now, target_rad_per_s, accel_magnitude_rad_per_s2);
}

const SpeedSegment& SpeedProfile::segment_at(double t_s) const {
  // Few segments: a linear scan from the back is the fastest and simplest.
  for (auto it = segments_.rbegin(); it != segments_.rend(); ++it) {
    if (it->start_time_s <= t_s) return *it;
  }
  return segments_.front();
}

double SpeedProfile::next_break_after(double t_s) const {
  for (const auto& s : segments_) {
    if (s.start_time_s > t_s) return s.start_time_s;
  }
  return std::numeric_limits<double>::infinity();
}

double SpeedProfile::time_at_angle(double t_s, double angle_rad) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < segments_.size(); ++i) {
    const SpeedSegment& seg = segments_[i];
    const double end = i + 1 < segments_.size() ? segments_[i + 1].start_time_s : kInf;
    if (end < t_s) continue;
    // phi(start + tau) = angle: 0.5 a tau^2 + w0 tau - delta = 0, delta >= 0.
    // The root written without cancellation: tau = 2 delta / (w0 + sqrt(w0^2 + 2 a delta)).
    // Rounding: a mark on a segment boundary may come out an ulp past the
    // end of one segment and an ulp before the start of the next; a few ulps
    // of slack on both sides keep it.
    const double slack_rad = 8.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(angle_rad));
    double delta = angle_rad - seg.start_angle_rad;
    if (delta < 0.0 && delta > -slack_rad) delta = 0.0;
    const double w0 = seg.start_speed_rad_per_s, a = seg.accel_rad_per_s2;
    const double disc = w0 * w0 + 2.0 * a * delta;
    if (delta < 0.0 || disc < 0.0) continue;
    const double denominator = w0 + std::sqrt(disc);
    if (!(denominator > 0.0)) continue;  // standing still: never
    const double t = seg.start_time_s + 2.0 * delta / denominator;
    const double slack_s = 8.0 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(end));
    if (t <= end + slack_s && t >= std::max(t_s, seg.start_time_s)) return std::min(t, end);
  }
  return kInf;
}

}  // namespace rotor_rub::core
