#include "rotor_rub_sim/core/flexible_rotor_model.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace rotor_rub::core {

FlexibleRotorModel::FlexibleRotorModel(const ReducedRotor& rotor, const std::vector<RotorUnbalance>& unbalances)
    : rotor_(rotor),
      station_mass_kg_(rotor.station_mass_kg),
      k_(rotor.matrices.K),
      c_(rotor.matrices.C),
      g_(rotor.matrices.G) {
  if (rotor.planar_modes > kMaxPlanarModes) {
    throw std::invalid_argument("flexible rotor: " + std::to_string(rotor.planar_modes) +
                                " planar modes; accepted: 1 to " + std::to_string(kMaxPlanarModes));
  }
  const int n = static_cast<int>(rotor.expansion.rows());
  Eigen::VectorXd a_full = Eigen::VectorXd::Zero(n), b_full = Eigen::VectorXd::Zero(n);
  for (const RotorUnbalance& u : unbalances) {
    if (u.node < 0 || 4 * u.node >= n) {
      throw std::invalid_argument("unbalance: node " + std::to_string(u.node) + " is out of range; accepted: 0 to " +
                                  std::to_string(n / 4 - 1));
    }
    // At spin angle 0 the force points along beta; a quarter turn on, along beta + pi/2.
    a_full(dof_index(u.node, kDofX)) += u.me_kg_m * std::cos(u.phase_rad);
    a_full(dof_index(u.node, kDofY)) += u.me_kg_m * std::sin(u.phase_rad);
    b_full(dof_index(u.node, kDofX)) -= u.me_kg_m * std::sin(u.phase_rad);
    b_full(dof_index(u.node, kDofY)) += u.me_kg_m * std::cos(u.phase_rad);
  }
  a_ = rotor.expansion.transpose() * a_full;
  b_ = rotor.expansion.transpose() * b_full;
}

}  // namespace rotor_rub::core
