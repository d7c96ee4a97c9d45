#include "modal_convergence.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rotor_rub::tools {
namespace {

// The worst relative error of r's `want.size()` lowest damped frequencies
// at each speed against the full model's (`want`, computed once: the full
// eigensolve is the study's cost); 1 when r has fewer modes.
double frequency_error(const std::vector<std::vector<core::Mode>>& want, const core::ReducedRotor& r,
                       const std::vector<double>& speeds) {
  double worst = 0.0;
  for (std::size_t s = 0; s < speeds.size(); ++s) {
    const auto got = core::modes(r, speeds[s], static_cast<int>(want[s].size()));
    if (got.size() < want[s].size()) return 1.0;
    for (std::size_t k = 0; k < want[s].size(); ++k) {
      worst =
          std::max(worst, std::abs(got[k].damped_frequency_rad_per_s / want[s][k].damped_frequency_rad_per_s - 1.0));
    }
  }
  return worst;
}

}  // namespace

std::vector<TruncationRow> truncation_rows(const core::FeRotor& rotor, const core::RotorMatrices& full,
                                           const TruncationStudy& study) {
  std::vector<int> watched{study.station_node};
  watched.insert(watched.end(), study.probe_nodes.begin(), study.probe_nodes.end());
  std::vector<double> speeds;
  for (int k = 1; k < study.speeds; ++k) speeds.push_back(study.max_speed_rad_per_s * k / (study.speeds - 1));
  const core::ResponseReference reference(rotor, full, study.unbalances, speeds, watched);
  std::vector<int> counts;
  for (int m = 1; m < core::max_planar_modes(rotor); m *= 2) counts.push_back(m);
  counts.push_back(core::max_planar_modes(rotor));
  const std::vector<double> frequency_speeds{0.0, study.max_speed_rad_per_s};
  std::vector<std::vector<core::Mode>> want;
  for (const double speed : frequency_speeds) want.push_back(core::modes(full, speed, study.modes));
  const core::RotorReduction reduction(rotor, full, study.station_node, counts.back());
  std::vector<TruncationRow> rows;
  for (const int m : counts) {
    const core::ReducedRotor r = reduction.reduce(m);
    TruncationRow row;
    row.planar_modes = m;
    row.station_mass_kg = r.station_mass_kg;
    row.frequency_error = frequency_error(want, r, frequency_speeds);
    row.response_error = reference.error(r);
    rows.push_back(row);
  }
  return rows;
}

const TruncationRow* smallest_within(const std::vector<TruncationRow>& rows, double tolerance) {
  for (const TruncationRow& row : rows) {
    if (row.worst() <= tolerance) return &row;
  }
  return nullptr;
}

}  // namespace rotor_rub::tools
