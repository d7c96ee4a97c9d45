// Output of a headless run: the CSV of samples, the JSON summary, and the
// figures a person reads (touchdown, lift-off, max orbit, max force, cost).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/simulation.hpp"

namespace rotor_rub::tools {

// Keeps the samples (when asked) and running maxima.
class RunRecorder : public core::SimulationObserver {
 public:
  explicit RunRecorder(bool keep_samples) : keep_samples_(keep_samples) {}
  void on_sample(const core::Sample& s) override;
  void on_event(const core::ContactEvent& e) override { events.push_back(e); }

  std::vector<core::Sample> samples;
  std::vector<core::ContactEvent> events;
  core::Sample last_sample;           // kept even when samples are not (the failure line)
  double max_orbit_m = 0.0;           // max |r_r| over the samples
  double max_normal_force_N = 0.0;    // max F_n over the samples
  double max_penetration_m = -1e300;  // max delta - C over the samples

 private:
  bool keep_samples_;
};

void write_csv(std::ostream& os, const std::vector<core::Sample>& samples);

struct SummaryInput {
  std::string scene_path;
  const core::Scene* scene;
  const RunRecorder* recorder;
  core::RunStats stats;
  const std::optional<core::RunFailure>* failure;
};
void write_summary_json(std::ostream& os, const SummaryInput& in);

// First touchdown / last lift-off time, or NaN when there is none.
double first_touchdown_s(const std::vector<core::ContactEvent>& events);
double last_liftoff_s(const std::vector<core::ContactEvent>& events);

}  // namespace rotor_rub::tools
