// Counts contact events in a sliding window of simulated time and fails the
// run when they come faster than max_events_per_ms (chattering / Zeno).
#pragma once

#include <deque>
#include <string>

#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

class ChatterGuard {
 public:
  explicit ChatterGuard(double max_events_per_ms) : max_per_window_(max_events_per_ms) {}

  void record(double t_s) {
    times_.push_back(t_s);
    while (!times_.empty() && times_.front() < t_s - kWindow_s) times_.pop_front();
    if (static_cast<double>(times_.size()) > max_per_window_) {
      throw MethodFailure(FailureClass::kStalled, t_s,
                          "chattering: " + std::to_string(times_.size()) +
                              " contact events within 1 ms of simulated time (max_events_per_ms)");
    }
  }

 private:
  static constexpr double kWindow_s = 1e-3;
  double max_per_window_;
  std::deque<double> times_;
};

}  // namespace rotor_rub::core
