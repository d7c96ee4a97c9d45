// The sweep's result table: one CSV row per run, and the merge of shards.
#pragma once

#include <limits>
#include <ostream>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/run_errors.hpp"
#include "sweep_grid.hpp"

namespace rotor_rub::tools {

struct SweepResult {
  std::size_t id = 0, runs_total = 0;
  Values overrides;    // the grid's values for this run
  core::Scene scene;   // the effective scene (valid unless status is "invalid")
  std::string status;  // ok | invalid | stalled | diverged | not_converged | no_reference
  double failure_time_s = 0.0;
  std::string message;       // the failure's, or why the run is invalid
  double wall_time_s = 0.0;  // median of the timed repeats (integration only)
  int repeats = 0;
  core::RunStats stats;                           // of a timed run
  double rhs_share = 0.0, iteration_share = 0.0;  // --profile only, else NaN
  core::RunErrors errors;
  double horizon_s = std::numeric_limits<double>::infinity();  // infinite without --witness
};

// The header line, without newline.
std::string sweep_csv_header();
void write_sweep_row(std::ostream& os, const SweepResult& r);

// Merges shard CSVs into one, rows in run order. Throws std::runtime_error
// when the headers differ or the runs are not each present exactly once.
void merge_sweep_csvs(const std::vector<std::string>& parts, std::ostream& out);

}  // namespace rotor_rub::tools
