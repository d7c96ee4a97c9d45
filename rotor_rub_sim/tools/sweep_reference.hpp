// The reference runs of a sweep: one per distinct physics (the run's scene
// with the solver settings replaced by the reference's), computed once,
// shared by every run with that physics across threads, and optionally cached
// on disk so that shards and later sweeps reuse it.
#pragma once

#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "rotor_rub_sim/core/run_errors.hpp"
#include "sweep_grid.hpp"

namespace rotor_rub::tools {

struct ReferenceSettings {
  double rtol = 1e-10;
  double atol = 1e-13;
  double sample_rate_hz = 20000.0;  // the grid the errors are measured on
  double window_s = 1e-3;           // impulse windows
  // A witness: the iteration method on dop853 at the same tolerances, an
  // independent event handling; where its orbit parts from the reference's by
  // more than horizon_apart_m ends the horizon the runs are judged in.
  bool witness = false;
  double horizon_apart_m = 1e-4;
};

class ReferenceStore {
 public:
  ReferenceStore(ReferenceSettings settings, std::string cache_dir)
      : settings_(settings), cache_dir_(std::move(cache_dir)) {}

  // The values of the reference for a run's scene values: switching,
  // dopri5, the reference tolerances, sampled at sample_rate_hz; the
  // method-only keys (contact stiffness, integrator, budgets) dropped.
  Values reference_values(const Values& run_values) const;
  // The witness's values for a reference's.
  static Values witness_values(const Values& reference_values);
  // Computes (or loads) the reference once per distinct values; thread-safe.
  std::shared_ptr<const core::ReferenceTrace> get(const Values& run_values);
  const ReferenceSettings& settings() const { return settings_; }

 private:
  std::shared_ptr<const core::ReferenceTrace> compute(const Values& ref_values, const std::string& key);
  ReferenceSettings settings_;
  std::string cache_dir_;
  std::mutex mutex_;
  std::map<std::string, std::shared_future<std::shared_ptr<const core::ReferenceTrace>>> traces_;
};

}  // namespace rotor_rub::tools
