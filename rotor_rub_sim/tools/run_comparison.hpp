// Offline comparison of recorded runs (from bags or the runner's CSV): the
// figures per run and the differences against a reference run. ROS-free; the
// bag reading lives in rotor_rub_compare.cpp.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::tools {

// A live change or fault the node applied (its parameter_change_feedback:
// one per change, a ramp's spanning its steps).
struct LiveChange {
  double t_s = 0.0;      // applied at (a ramp's first step)
  double end_s = 0.0;    // a ramp's last step; t_s for a step
  std::string what;      // a fault's kind, or "key=value ..." (no commas)
  std::uint32_t id = 0;  // the request's change_id (a fault's fault_id)
  std::string from;      // "key=value ..." before it
  std::string values;    // "key=value ..." as applied (a fault's too; a ramp's at its end)
  std::uint32_t steps = 1;
};

struct RecordedRun {
  std::string name;        // e.g. "paper.bag:/switching/rotor_rub_sim"
  std::string method;      // from the last SolverStats or the summary, or "" when unknown
  std::string integrator;  // the one that ran (auto resolved), as method
  std::vector<core::Sample> samples;
  std::vector<core::ContactEvent> events;
  bool has_events = false;          // a CSV without its JSON summary has none
  long lost_samples = 0;            // gaps in the state messages' sample index
  std::vector<LiveChange> changes;  // applied, in time order (bags only)
  // The last SolverStats (bags only; -1 when unknown).
  long steps = -1, rhs_evals = -1;
  double integration_wall_s = -1.0, real_time_factor = -1.0;
};

struct RunFigures {
  std::string name, method, integrator;
  std::size_t samples = 0;
  long lost_samples = 0;
  double first_contact_s, first_touchdown_s, last_liftoff_s, last_contact_end_s;
  long touchdowns = 0, liftoffs = 0, grazes = 0;
  double max_orbit_m = 0.0, max_normal_force_N = 0.0;
  double mean_normal_force_in_contact_N;  // over samples in contact
  double contact_time_s = 0.0;            // samples in contact x sample period
  // Against the reference, on the sample times both runs have.
  std::size_t common_samples = 0;
  double max_rotor_diff_m, rms_rotor_diff_m, max_stator_diff_m, rms_stator_diff_m, max_normal_force_diff_N;
  double first_contact_diff_s, last_contact_end_diff_s;
  long steps = -1, rhs_evals = -1;
  double integration_wall_s = -1.0, real_time_factor = -1.0;
  // Live changes and faults: how many, the first one's time, the first
  // contact at or after it (a fault's effect), and all as "t what; ...". A
  // ramp (a fault's steps: one id, one kind, one after another) counts as
  // one, "t0..t1 kind key=first..last (n steps)".
  long live_changes = 0;
  double first_change_s, first_contact_after_change_s;
  std::string changes;
};

RunFigures compare_run(const RecordedRun& run, const RecordedRun& reference);

// A fixed-width table for people and a CSV (one row per run) for scripts.
void print_table(std::ostream& os, const std::vector<RunFigures>& rows, const std::string& reference_name);
void write_figures_csv(std::ostream& os, const std::vector<RunFigures>& rows);

// The runner's CSV (rotor_rub_run --csv) and, if present, the events of its
// JSON summary. Throws std::runtime_error naming the file on a bad file.
RecordedRun read_runner_csv(const std::string& csv_path, const std::string& summary_path);

}  // namespace rotor_rub::tools
