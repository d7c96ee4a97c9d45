// Error measures of a run against a reference run sampled at the same times.
#pragma once

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

struct TrajectoryError {
  double max_rotor_x_m = 0.0;  // max |x_r - x_r,ref|
  double rms_rotor_x_m = 0.0;
  double max_rotor_m = 0.0;   // max |r_r - r_r,ref|
  double max_stator_m = 0.0;  // max |r_s - r_s,ref|
  std::size_t samples = 0;
};

// Both runs sampled on the same grid; compares the common prefix (a failed
// run is shorter). Throws std::invalid_argument if the grids differ.
inline TrajectoryError compare_trajectories(const std::vector<Sample>& run, const std::vector<Sample>& ref) {
  TrajectoryError e;
  const std::size_t n = std::min(run.size(), ref.size());
  double sum2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (run[i].t_s != ref[i].t_s) throw std::invalid_argument("compare_trajectories: sample times differ");
    const double dx = run[i].kin.rotor_pos.x() - ref[i].kin.rotor_pos.x();
    e.max_rotor_x_m = std::max(e.max_rotor_x_m, std::abs(dx));
    sum2 += dx * dx;
    e.max_rotor_m = std::max(e.max_rotor_m, (run[i].kin.rotor_pos - ref[i].kin.rotor_pos).norm());
    e.max_stator_m = std::max(e.max_stator_m, (run[i].kin.stator_pos - ref[i].kin.stator_pos).norm());
  }
  e.rms_rotor_x_m = n ? std::sqrt(sum2 / static_cast<double>(n)) : 0.0;
  e.samples = n;
  return e;
}

// The first contact (touchdown or graze): methods classify the first touch
// differently (a plastic rigid touch that does not stay is a graze, a penalty
// contact is a touchdown however short), but all agree on when it happens.
inline double first_contact_s(const std::vector<ContactEvent>& events) {
  for (const auto& ev : events) {
    if (ev.kind != EventKind::kLiftoff) return ev.t_s;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// The end of the last contact: the last lift-off, or a later graze.
inline double last_contact_end_s(const std::vector<ContactEvent>& events) {
  for (auto it = events.rbegin(); it != events.rend(); ++it) {
    if (it->kind != EventKind::kTouchdown) return it->t_s;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

// Start and end of the longest sustained contact interval (touchdown to the
// following lift-off), NaN if none.
// A contact still on at the run's end lasts until end_s when that is given
// (the time the run reached); without it, only contacts that ended count.
inline std::pair<double, double> longest_contact(const std::vector<ContactEvent>& events, double end_s = std::nan("")) {
  std::pair<double, double> best{std::nan(""), std::nan("")};
  double start = std::nan("");
  auto consider = [&best](double a, double b) {
    if (!std::isfinite(best.first) || b - a > best.second - best.first) best = {a, b};
  };
  for (const auto& ev : events) {
    if (ev.kind == EventKind::kTouchdown) start = ev.t_s;
    if (ev.kind == EventKind::kLiftoff && std::isfinite(start)) {
      consider(start, ev.t_s);
      start = std::nan("");
    }
  }
  if (std::isfinite(start) && std::isfinite(end_s) && end_s >= start) consider(start, end_s);
  return best;
}

}  // namespace rotor_rub::core
