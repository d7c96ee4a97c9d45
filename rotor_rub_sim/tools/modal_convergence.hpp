// The modal truncation study of rotor_rub_modal --station: the reduced
// rotor (rotor_reduction.hpp) at 1, 2, 4, ... planar modes against the full
// FE model, on the user's own rotor, and the smallest model within a
// tolerance.
#pragma once

#include <vector>

#include "rotor_rub_sim/core/rotor_reduction.hpp"

namespace rotor_rub::tools {

struct TruncationRow {
  int planar_modes = 0;
  double station_mass_kg = 0.0;
  /// The worst relative error of the `modes` lowest damped frequencies at rest
  /// and at the top speed (1 when the reduced model has fewer such modes).
  double frequency_error = 0.0;
  /// The worst error of the unbalance response at the station and the probe
  /// nodes over the speed grid, relative to the rotor's largest displacement
  /// at each speed (0 without an unbalance).
  double response_error = 0.0;
  double worst() const { return frequency_error > response_error ? frequency_error : response_error; }
};

struct TruncationStudy {
  int station_node = 0;
  std::vector<int> probe_nodes;
  int modes = 4;  ///< frequencies compared
  double max_speed_rad_per_s = 1000.0;
  int speeds = 101;                              ///< response grid: max_speed k / (speeds - 1), k = 1 .. speeds - 1
  std::vector<core::RotorUnbalance> unbalances;  ///< none: no response compared
};

/// Rows for 1, 2, 4, ... planar modes and the rotor's maximum. Throws
/// std::invalid_argument for a station or probe node out of range.
std::vector<TruncationRow> truncation_rows(const core::FeRotor& rotor, const core::RotorMatrices& full,
                                           const TruncationStudy& study);

/// The first row whose errors are all within tolerance (rows ascend), or nullptr.
const TruncationRow* smallest_within(const std::vector<TruncationRow>& rows, double tolerance);

}  // namespace rotor_rub::tools
