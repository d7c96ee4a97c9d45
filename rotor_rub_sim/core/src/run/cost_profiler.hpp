// Opt-in measurement of where a run's time goes (derivative evaluation,
// force iteration), for the benchmark's Table-2 shares. Off by default: the
// clock reads would cost a noticeable part of a right-hand side.
#pragma once

#include <chrono>

namespace rotor_rub::core {

class ProfileScope {
 public:
  // accumulator == nullptr: profiling off, nothing is measured.
  explicit ProfileScope(double* accumulator_s) : acc_(accumulator_s) {
    if (acc_) start_ = std::chrono::steady_clock::now();
  }
  ~ProfileScope() {
    if (acc_) *acc_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  ProfileScope(const ProfileScope&) = delete;
  ProfileScope& operator=(const ProfileScope&) = delete;

 private:
  double* acc_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace rotor_rub::core
