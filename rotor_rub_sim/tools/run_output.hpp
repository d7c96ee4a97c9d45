// Output of a headless run: the CSV of samples, the JSON summary, and the
// figures a person reads (touchdown, lift-off, max orbit, max force, cost).
#pragma once

#include <cmath>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/probes.hpp"
#include "rotor_rub_sim/core/simulation.hpp"

namespace rotor_rub::tools {

// Keeps the samples (when asked), running maxima, and (when asked) the
// keyphasor marks, the probes' signals and a flexible rotor's shaft (at
// shaft_rate_hz > 0).
class RunRecorder : public core::SimulationObserver {
 public:
  explicit RunRecorder(bool keep_samples, bool keep_marks = false, const core::ProbeParameters* probes = nullptr,
                       double shaft_rate_hz = 0.0)
      : keep_samples_(keep_samples), keep_marks_(keep_marks), shaft_rate_hz_(shaft_rate_hz) {
    if (probes != nullptr) probe_pair_.emplace(*probes);
  }
  void on_sample(const core::Sample& s) override;
  void on_event(const core::ContactEvent& e) override { events.push_back(e); }
  bool wants_keyphasor() const override { return keep_marks_; }
  void on_keyphasor(const core::Sample& s) override { marks.push_back(s); }
  bool wants_probes() const override { return probe_pair_.has_value(); }
  void on_probe_sample(const core::Sample& s) override { probe_readings.push_back(probe_pair_->read(s)); }
  double shaft_rate_hz() const override { return shaft_rate_hz_; }
  void on_shaft_sample(const core::ShaftSample& s) override { shaft.push_back(s); }

  std::vector<core::Sample> marks;                 // the keyphasor's states
  std::vector<core::ProbeReading> probe_readings;  // the probes' signals
  std::vector<core::ShaftSample> shaft;            // a flexible rotor's nodes

  std::vector<core::Sample> samples;
  std::vector<core::ContactEvent> events;
  core::Sample last_sample;           // kept even when samples are not (the failure line)
  double max_orbit_m = 0.0;           // max |r_r| over the samples
  double max_normal_force_N = 0.0;    // max F_n over the samples
  double max_penetration_m = -1e300;  // max delta - C over the samples

 private:
  bool keep_samples_, keep_marks_;
  double shaft_rate_hz_;
  std::optional<core::ProbePair> probe_pair_;
};

// The keyphasor's marks: t, revolution (1, 2, ...), spin speed; and the
// probes' signals: t, x_V, y_V and what they measure without noise, x_m, y_m.
void write_keyphasor_csv(std::ostream& os, const std::vector<core::Sample>& marks);
void write_probes_csv(std::ostream& os, const std::vector<core::ProbeReading>& readings);
// A flexible rotor's shaft, a row per node and sample: t, node, z_m (its
// position along the shaft), x_m, y_m (its lateral displacement).
void write_shaft_csv(std::ostream& os, const std::vector<core::ShaftSample>& shaft,
                     const std::vector<double>& node_z_m);

void write_csv(std::ostream& os, const std::vector<core::Sample>& samples);

struct SummaryInput {
  std::string scene_path;
  const core::Scene* scene;
  const RunRecorder* recorder;
  core::RunStats stats;
  const std::optional<core::RunFailure>* failure;
  double end_time_s = std::nan("");  // the time the run reached (a contact still on ends there)
  core::Simulation::ContactPoint contact_point;
  core::Simulation::Reduction reduction;  // a flexible rotor's (planar_modes 0: the Jeffcott)
};
void write_summary_json(std::ostream& os, const SummaryInput& in);

// First touchdown / last lift-off time, or NaN when there is none.
double first_touchdown_s(const std::vector<core::ContactEvent>& events);
double last_liftoff_s(const std::vector<core::ContactEvent>& events);

}  // namespace rotor_rub::tools
