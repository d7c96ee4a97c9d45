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
  q_.resize(k_.rows());
  q_dot_.resize(k_.rows());
  f_.resize(k_.rows());
}

void FlexibleRotorModel::free_loads(const Vec2& u, const Vec2& u_dot, const Eigen::VectorXd& xi,
                                    const Eigen::VectorXd& xi_dot, const DriveState& d, FreeLoads& out) const {
  const int m = modal_size();
  if (xi.size() != m || xi_dot.size() != m) {
    throw std::invalid_argument("FlexibleRotorModel: " + std::to_string(xi.size()) + " and " +
                                std::to_string(xi_dot.size()) + " modal coordinates given; the model has " +
                                std::to_string(m));
  }
  q_.head<2>() = u;
  q_.tail(m) = xi;
  q_dot_.head<2>() = u_dot;
  q_dot_.tail(m) = xi_dot;
  const double c = std::cos(d.angle_rad), s = std::sin(d.angle_rad), w2 = d.speed_rad_per_s * d.speed_rad_per_s;
  const double A = d.accel_rad_per_s2;
  f_.noalias() = -k_ * q_;
  f_.noalias() -= c_ * q_dot_;
  f_.noalias() -= d.speed_rad_per_s * (g_ * q_dot_);
  f_ += (w2 * c + A * s) * a_ + (w2 * s - A * c) * b_;
  out.station_N = f_.head<2>();
  out.modal_acc = f_.tail(m);  // M = I on the modal block
}

}  // namespace rotor_rub::core
