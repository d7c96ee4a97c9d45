#include "modal_convergence.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rotor_rub::tools {
namespace {

double frequency_error(const core::RotorMatrices& full, const core::ReducedRotor& r, int count, double top_speed) {
  double worst = 0.0;
  for (double speed : {0.0, top_speed}) {
    const auto want = core::modes(full, speed, count);
    const auto got = core::modes(r, speed, count);
    if (got.size() < want.size()) return 1.0;
    for (std::size_t k = 0; k < want.size(); ++k) {
      worst = std::max(worst, std::abs(got[k].damped_frequency_rad_per_s / want[k].damped_frequency_rad_per_s - 1.0));
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
  const core::RotorReduction reduction(rotor, full, study.station_node, counts.back());
  std::vector<TruncationRow> rows;
  for (const int m : counts) {
    const core::ReducedRotor r = reduction.reduce(m);
    TruncationRow row;
    row.planar_modes = m;
    row.station_mass_kg = r.station_mass_kg;
    row.frequency_error = frequency_error(full, r, study.modes, study.max_speed_rad_per_s);
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
