// The reference runs of a sweep: one per distinct physics (the run's scene
// with the solver settings replaced by the reference's), computed once,
// shared by every run with that physics across threads, and optionally cached
// on disk so that shards and later sweeps reuse it.
#pragma once

#include <future>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/run_errors.hpp"
#include "sweep_grid.hpp"

namespace rotor_rub::tools {

struct ReferenceSettings {
  double rtol = 1e-10;
  double atol = 1e-13;
  double sample_rate_hz = 20000.0;  // the grid the errors are measured on
  double window_s = 1e-3;           // impulse windows
  // Judge runs within a horizon (--witness): see ReferenceStore::judge.
  bool witness = false;
  double horizon_apart_m = 1e-4;
};

// A run's reference and the time up to which it is judged against it.
struct Judged {
  std::shared_ptr<const core::ReferenceTrace> reference;
  double horizon_s = std::numeric_limits<double>::infinity();
  std::string witness_failures;  // witnesses that failed (each ends the horizon at its failure)
};

class ReferenceStore {
 public:
  ReferenceStore(ReferenceSettings settings, std::string cache_dir)
      : settings_(settings), cache_dir_(std::move(cache_dir)) {}

  // The values of the reference for a run's scene values: switching,
  // dopri5, the reference tolerances, sampled at sample_rate_hz; the
  // method-only keys (contact stiffness, integrator, budgets) dropped.
  Values reference_values(const Values& run_values) const;
  // The reference, computed (or loaded) once per distinct values and shared
  // across threads, and with settings().witness the horizon: where the first
  // of these leaves its orbit by more than horizon_apart_m, the time from
  // which two runs the run's precision cannot tell apart part (chaos,
  // grazing), so that an error against the reference says nothing about the
  // method: the reference with the bore moved by the run's atol (what the
  // run's own precision amplifies), and the switching and iteration methods
  // on dop853 at the reference's tolerances (another integrator, another
  // event handling: what the reference's precision amplifies).
  Judged judge(const Values& run_values, double run_atol_m);
  const ReferenceSettings& settings() const { return settings_; }

 private:
  // The trace of final values (a reference's or a witness's), memoised; thread-safe.
  std::shared_ptr<const core::ReferenceTrace> trace_of(const Values& ref_values);
  std::shared_ptr<const core::ReferenceTrace> compute(const Values& ref_values, const std::string& key);
  ReferenceSettings settings_;
  std::string cache_dir_;
  std::mutex mutex_;
  std::map<std::string, std::shared_future<std::shared_ptr<const core::ReferenceTrace>>> traces_;
};

}  // namespace rotor_rub::tools
