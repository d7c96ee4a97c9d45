// RK4's stability bound from a linear system's eigenvalues (rk4_stability.hpp).
#include "integrators/rk4_stability.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "contact/penalty_law.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/fe_rotor.hpp"

namespace rotor_rub::core {

double rk4_stable_step_s(std::complex<double> lambda) {
  const double size = std::abs(lambda);
  if (size == 0.0) return std::numeric_limits<double>::infinity();
  if (lambda.real() >= 0.0) return 2.0 * std::sqrt(2.0) / size;
  const std::complex<double> direction = lambda / size;
  auto gain = [&](double r) {
    const std::complex<double> z = r * direction;
    return std::abs(1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0))));
  };
  // |R| = 1 within rounding counts as stable: near the imaginary axis the
  // region's edge and the ray run side by side.
  constexpr double kRounding = 1e-12;
  // RK4's region lies inside |z| < 3 (|R| ~ |z|^4 / 24 beyond): scan the ray
  // for the first |R| > 1, then bisect on that interval.
  constexpr double kScan = 1e-3;
  double lo = 0.0, hi = kScan;
  while (gain(hi) <= 1.0 + kRounding) {
    lo = hi;
    hi += kScan;
  }
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (gain(mid) <= 1.0 + kRounding ? lo : hi) = mid;
  }
  return lo / size;
}

double rk4_stable_step_s(const JeffcottModel& m) {
  const double zeta = contact_damping_ratio(m);
  const double omega_c = std::sqrt(m.parameters().contact_stiffness_N_per_m / m.effective_mass_kg());
  const std::complex<double> contact = zeta >= 1.0
                                           ? std::complex<double>(-omega_c * (zeta + std::sqrt(zeta * zeta - 1.0)), 0.0)
                                           : omega_c * std::complex<double>(-zeta, std::sqrt(1.0 - zeta * zeta));
  double h = rk4_stable_step_s(contact);
  if (m.has_friction()) {
    double spin_share = 1.0;
    if (m.motor()) {
      const ModelParameters& p = m.parameters();
      const double lever = p.rotor_radius_m + p.eccentricity_m;
      spin_share += lever * lever * m.effective_mass_kg() / p.rotor_polar_inertia_kg_m2;
    }
    h = std::min(h, rk4_stable_step_s(-2.0 * spin_share * omega_c));
  }
  if (m.motor()) {
    // The speed controller on the spin, J_G s^2 + K_p s + K_i = 0, and in
    // the torque limit the anti-windup's -K_i / K_p.
    const ModelParameters& p = m.parameters();
    const double j = p.rotor_polar_inertia_kg_m2, kp = p.drive_proportional_gain_N_m_s_per_rad,
                 ki = p.drive_integral_gain_N_m_per_rad;
    const std::complex<double> root = std::sqrt(std::complex<double>(kp * kp - 4.0 * j * ki, 0.0));
    h = std::min({h, rk4_stable_step_s((-kp + root) / (2.0 * j)), rk4_stable_step_s((-kp - root) / (2.0 * j)),
                  rk4_stable_step_s(-ki / kp)});
  }
  return h;
}

double flexible_rk4_stable_step_s(const FlexibleRotorModel& rotor, const ModelParameters& scene_model,
                                  double max_speed_rad_per_s) {
  const ModelParameters p = station_parameters(scene_model, rotor);
  const PenaltyLaw law{StationModel(p)};
  const RotorMatrices& r = rotor.rotor().matrices;
  const int n_rotor = static_cast<int>(r.M.rows());
  const bool elastic = p.stator_model == StatorModel::kElastic;
  const bool motor = p.drive_model == DriveModel::kMotor;
  const int stator = n_rotor;                    // the stator's x, y (elastic)
  const int spin = n_rotor + (elastic ? 2 : 0);  // the spin angle (motor)
  const int n = spin + (motor ? 1 : 0);
  RotorMatrices free;
  for (Eigen::MatrixXd* x : {&free.M, &free.K, &free.C, &free.G}) x->setZero(n, n);
  free.M.topLeftCorner(n_rotor, n_rotor) = r.M;
  free.K.topLeftCorner(n_rotor, n_rotor) = r.K;
  free.C.topLeftCorner(n_rotor, n_rotor) = r.C;
  free.G.topLeftCorner(n_rotor, n_rotor) = r.G;
  if (elastic) {
    for (int i = 0; i < 2; ++i) {
      free.M(stator + i, stator + i) = p.stator_mass_kg;
      free.K(stator + i, stator + i) = p.stator_stiffness_N_per_m;
      free.C(stator + i, stator + i) = p.stator_damping_N_s_per_m;
    }
  }
  const double spin_lever_kg_m2 = rotor.max_spin_lever_kg_m2();
  if (motor) {
    // The speed controller: K_p a damper and K_i a spring on the spin angle
    // (its integral state is the angle's lag behind the reference).
    free.M(spin, spin) = p.rotor_polar_inertia_kg_m2 - spin_lever_kg_m2;
    free.C(spin, spin) = p.drive_proportional_gain_N_m_s_per_rad;
    free.K(spin, spin) = p.drive_integral_gain_N_m_per_rad;
  }

  // In the torque limit the anti-windup's integral decays at -K_i / K_p.
  double h = motor ? rk4_stable_step_s(-p.drive_integral_gain_N_m_per_rad / p.drive_proportional_gain_N_m_s_per_rad)
                   : std::numeric_limits<double>::infinity();
  // The normal along x, then along y; t a quarter turn on.
  for (const Vec2& normal : {Vec2(1.0, 0.0), Vec2(0.0, 1.0)}) {
    const Vec2 tangent(-normal.y(), normal.x());
    // g_n . q: the penetration's change; g_t . q': the sliding velocity's.
    Eigen::VectorXd g_n = Eigen::VectorXd::Zero(n), g_t = Eigen::VectorXd::Zero(n);
    g_n.segment<2>(ReducedRotor::kStationX) = normal;
    g_t.segment<2>(ReducedRotor::kStationX) = tangent;
    if (elastic) {
      g_n.segment<2>(stator) = -normal;
      g_t.segment<2>(stator) = -tangent;
    }
    if (motor) g_t(spin) = p.rotor_radius_m + std::sqrt(spin_lever_kg_m2 / rotor.station_mass_kg());
    RotorMatrices pressed = free;
    pressed.K += law.stiffness_N_per_m * g_n * g_n.transpose();
    pressed.C += law.damping_N_s_per_m * g_n * g_n.transpose();
    // The friction's regimes: none, stick (the damper), slip either way
    // (F_t = -slip f F_n: the normal force's spring and damper reach the
    // tangential direction, a non-symmetric coupling).
    std::vector<RotorMatrices> regimes{pressed};
    if (law.has_friction()) {
      regimes.back().C += law.tangential_damping_N_s_per_m * g_t * g_t.transpose();
      for (const double slip : {1.0, -1.0}) {
        regimes.push_back(pressed);
        const double share = slip * law.friction_coefficient;
        regimes.back().K += share * law.stiffness_N_per_m * g_t * g_n.transpose();
        regimes.back().C += share * law.damping_N_s_per_m * g_t * g_n.transpose();
      }
    }
    for (const RotorMatrices& m : regimes) {
      for (const double speed : {0.0, max_speed_rad_per_s}) {
        const Eigen::VectorXcd lambda = eigenvalues(m, speed);
        for (Eigen::Index i = 0; i < lambda.size(); ++i) h = std::min(h, rk4_stable_step_s(lambda(i)));
      }
    }
  }
  return h;
}

}  // namespace rotor_rub::core
