#include "rotor_rub_sim/core/rotor_steady_response.hpp"

#include <Eigen/LU>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rotor_rub_sim/core/rotor_reduction.hpp"
#include "rotor_rub_sim/core/steady_response.hpp"

namespace rotor_rub::core {
namespace {
using cd = std::complex<double>;
}  // namespace

std::vector<FlexibleFullRub> synchronous_full_rub(const RotorMatrices& m, int station_node,
                                                  const std::vector<RotorUnbalance>& unbalances,
                                                  const StationStator& stator, double clearance_m,
                                                  double friction_coefficient, double w) {
  const int n = static_cast<int>(m.M.rows()), nodes = (n - 2 * m.support_nodes) / 4;
  auto check_node = [nodes](int node, const std::string& what) {
    if (node < 0 || node >= nodes) {
      throw std::invalid_argument(what + ": node " + std::to_string(node) + " is out of range; accepted: 0 to " +
                                  std::to_string(nodes - 1));
    }
  };
  check_node(station_node, "rub station");
  const int x = dof_index(station_node, kDofX), y = dof_index(station_node, kDofY);
  const Eigen::PartialPivLU<Eigen::MatrixXcd> lu(dynamic_stiffness(m, w));
  // The response to a unit forward force at the station (its receptance).
  Eigen::VectorXcd unit = Eigen::VectorXcd::Zero(n);
  unit(x) = 1.0;
  unit(y) = cd(0.0, -1.0);
  const Eigen::VectorXcd by_unit = lu.solve(unit),
                         by_unbalance = lu.solve(unbalance_forces(n, unbalances, w, m.support_nodes));
  // Forward: y = -i x at the station. An anisotropic rotor answers a
  // forward force with a backward part too (elliptic orbits).
  if (std::abs(by_unit(y) + cd(0.0, 1.0) * by_unit(x)) > 1e-9 * std::abs(by_unit(x)) ||
      std::abs(by_unbalance(y) + cd(0.0, 1.0) * by_unbalance(x)) > 1e-9 * std::abs(by_unbalance(x))) {
    throw std::invalid_argument(
        "synchronous full rub: the rotor is not isotropic (a bearing with kxx != kyy or kxy != -kyx, or its "
        "damping alike): its orbits are ellipses, not the circles of a full annular rub");
  }
  const cd h = by_unit(x), u0 = by_unbalance(x);
  const cd hs = stator.rigid
                    ? cd(0.0)
                    : 1.0 / cd(stator.stiffness_N_per_m - stator.mass_kg * w * w, stator.damping_N_s_per_m * w);
  const cd g = cd(1.0, friction_coefficient) * (h + hs);
  std::vector<FlexibleFullRub> out;
  if (!(std::abs(u0) > 0.0)) return out;  // no unbalance moves the station: nothing presses it on the bore
  for (const double normal_force : positive_circle_roots(clearance_m, g, std::abs(u0))) {
    const cd normal = u0 / (clearance_m + normal_force * g);                    // n at spin angle 0
    const cd contact = -normal_force * cd(1.0, friction_coefficient) * normal;  // on the rotor
    FlexibleFullRub s;
    s.normal_force_N = normal_force;
    s.response = by_unbalance + contact * by_unit;
    s.station_m = s.response(x);
    s.stator_m = -hs * contact;
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace rotor_rub::core
