#include "rotor_rub_sim/core/full_rub_stability.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rotor_rub::core {
namespace {

using cd = std::complex<double>;

bool rigid_stator(const ModelParameters& p) { return p.stator_model == StatorModel::kRigid; }

// The equilibrium as a state [q; q'] (velocities 0 in the turning frame).
Eigen::VectorXd equilibrium_state(const ModelParameters& p, const FullRub& rub) {
  const double theta = std::arg(rub.rotor_m - rub.stator_m);
  if (rigid_stator(p)) return (Eigen::VectorXd(2) << theta, 0.0).finished();
  return (Eigen::VectorXd(6) << rub.stator_m.real(), rub.stator_m.imag(), theta, 0.0, 0.0, 0.0).finished();
}

}  // namespace

Eigen::VectorXd full_rub_rates(const ModelParameters& p, double w, const Eigen::VectorXd& state,
                               double* normal_force_N) {
  const double m = p.rotor_mass_kg, c = p.rotor_damping_N_s_per_m, k = p.rotor_stiffness_N_per_m;
  const double C = p.clearance_m, f = p.friction_coefficient;
  const cd F = m * p.eccentricity_m * w * w * std::polar(1.0, p.unbalance_phase_rad);
  const cd I(0.0, 1.0);
  const bool rigid = rigid_stator(p);
  const int q = rigid ? 1 : 3;  // coordinates
  const double theta = state(q - 1), theta_rate = state(2 * q - 1);
  const cd u_s = rigid ? cd(0.0) : cd(state(0), state(1));
  const cd v_s = rigid ? cd(0.0) : cd(state(3), state(4));
  const cd n = std::polar(1.0, theta), t = I * n, fn = cd(1.0, f) * n;
  const cd u_r = u_s + C * n, v_r = v_s + C * theta_rate * t;
  // The rotor's equation less its unknown accelerations and N, and the stator's.
  const cd rotor_rest = F - (m * (-C * theta_rate * theta_rate * n + 2.0 * I * w * v_r - w * w * u_r) +
                             c * (v_r + I * w * u_r) + k * u_r);
  // Unknowns: [u_s'' (x, y), theta'', N] (elastic) or [theta'', N] (rigid).
  const int unknowns = rigid ? 2 : 4;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(unknowns, unknowns);
  Eigen::VectorXd b(unknowns);
  const int th = rigid ? 0 : 2, nf = rigid ? 1 : 3;
  // The rotor's x and y rows.
  for (int row = 0; row < 2; ++row) {
    auto part = [row](cd z) { return row == 0 ? z.real() : z.imag(); };
    if (!rigid) a(row, row) = m;
    a(row, th) = m * C * part(t);
    a(row, nf) = part(fn);
    b(row) = part(rotor_rest);
  }
  if (!rigid) {
    const double ms = p.stator_mass_kg, cs = p.stator_damping_N_s_per_m, ks = p.stator_stiffness_N_per_m;
    const cd stator_rest = -(ms * (2.0 * I * w * v_s - w * w * u_s) + cs * (v_s + I * w * u_s) + ks * u_s);
    for (int row = 0; row < 2; ++row) {
      auto part = [row](cd z) { return row == 0 ? z.real() : z.imag(); };
      a(2 + row, row) = ms;
      a(2 + row, nf) = -part(fn);
      b(2 + row) = part(stator_rest);
    }
  }
  const Eigen::VectorXd x = a.fullPivLu().solve(b);
  if (normal_force_N != nullptr) *normal_force_N = x(nf);
  Eigen::VectorXd rates(2 * q);
  rates.head(q) = state.tail(q);
  if (rigid) {
    rates(1) = x(0);
  } else {
    rates.tail(3) = x.head(3);
  }
  return rates;
}

std::vector<FullRubStability> full_rub_stability(const ModelParameters& p, double w) {
  if (p.gravity_m_per_s2 != 0.0) {
    throw std::invalid_argument("full rub stability: gravity_m_per_s2 must be 0 (it breaks the circular symmetry)");
  }
  if (p.drive_model != DriveModel::kPrescribed) {
    throw std::invalid_argument("full rub stability: the prescribed drive only (drive_model prescribed)");
  }
  std::vector<FullRubStability> out;
  for (const FullRub& rub : synchronous_full_rub(p, w)) {
    FullRubStability s;
    s.rub = rub;
    const Eigen::VectorXd x0 = equilibrium_state(p, rub);
    const int n = static_cast<int>(x0.size()), q = n / 2;
    s.jacobian.resize(n, n);
    // Central differences, each coordinate on its own scale (C, 1 rad, w C, w).
    for (int j = 0; j < n; ++j) {
      const bool angle = j % q == q - 1;
      const double scale = (angle ? 1.0 : p.clearance_m) * (j >= q ? w : 1.0);
      const double h = 1e-6 * scale;
      Eigen::VectorXd up = x0, down = x0;
      up(j) += h;
      down(j) -= h;
      s.jacobian.col(j) = (full_rub_rates(p, w, up) - full_rub_rates(p, w, down)) / (2.0 * h);
    }
    const Eigen::VectorXcd lambda = Eigen::EigenSolver<Eigen::MatrixXd>(s.jacobian).eigenvalues();
    s.eigenvalues.assign(lambda.data(), lambda.data() + lambda.size());
    std::sort(s.eigenvalues.begin(), s.eigenvalues.end(),
              [](cd a, cd b) { return a.real() != b.real() ? a.real() > b.real() : a.imag() > b.imag(); });
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<std::complex<double>> rigid_full_rub_eigenvalues(const ModelParameters& p, double w, const FullRub& rub) {
  const double m = p.rotor_mass_kg, C = p.clearance_m, f = p.friction_coefficient;
  const double phi = std::arg(rub.rotor_m) - p.unbalance_phase_rad;
  const double a = m * C, b = (p.rotor_damping_N_s_per_m + 2.0 * f * m * w) * C;
  const double c = m * p.eccentricity_m * w * w * (std::cos(phi) - f * std::sin(phi));
  const cd root = std::sqrt(cd(b * b - 4.0 * a * c));
  std::vector<cd> out{(-b + root) / (2.0 * a), (-b - root) / (2.0 * a)};
  std::sort(out.begin(), out.end(),
            [](cd x, cd y) { return x.real() != y.real() ? x.real() > y.real() : x.imag() > y.imag(); });
  return out;
}

}  // namespace rotor_rub::core
