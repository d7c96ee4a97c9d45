#include "rotor_rub_sim/core/steady_response.hpp"

#include <boost/math/tools/roots.hpp>
#include <cmath>
#include <cstdint>
#include <limits>

namespace rotor_rub::core {

using cd = std::complex<double>;

std::complex<double> unbalance_response_m(const ModelParameters& p, double w) {
  const double m = p.rotor_mass_kg;
  return m * p.eccentricity_m * w * w * std::polar(1.0, p.unbalance_phase_rad) /
         cd(p.rotor_stiffness_N_per_m - m * w * w, p.rotor_damping_N_s_per_m * w);
}

std::vector<double> positive_circle_roots(std::complex<double> a, std::complex<double> b, double r) {
  // |a + N b|^2 = r^2:  |b|^2 N^2 + 2 Re(a conj(b)) N + |a|^2 - r^2 = 0.
  const double bb = std::norm(b), ab = std::real(a * std::conj(b)), c0 = std::norm(a) - r * r;
  const double disc = ab * ab - bb * c0;
  std::vector<double> out;
  if (disc < 0.0 || bb == 0.0) return out;
  const double sq = std::sqrt(disc);
  // The two roots without cancellation (Vieta for the smaller one).
  const double big = (-ab + (ab <= 0.0 ? sq : -sq)) / bb;
  const double other = big != 0.0 ? c0 / (bb * big) : 0.0;
  for (const double N : {std::max(big, other), std::min(big, other)}) {
    if (N > 0.0 && (out.empty() || N != out.front())) out.push_back(N);
  }
  return out;
}

namespace {

// The full rub's equation |a + N b| = r at w (synchronous_full_rub), with
// what its solutions are built from.
struct FullRubCircle {
  cd a, b, A, B, F;
  double r;
  bool rigid;
};

FullRubCircle full_rub_circle(const ModelParameters& p, double w) {
  // Rotor:  A z_r = F - N (1 + i f) n,  stator: B z_s = N (1 + i f) n,
  // n = (z_r - z_s) / C, with A = k_r - m_r w^2 + i c_r w, F = m_r e w^2,
  // B = k_s - m_s w^2 + i c_s w (F turned by the unbalance's phase beta). With q = N (1 + i f) / C:
  //   z_s = q z_r / (B + q),  z_r - z_s = B z_r / (B + q),
  //   z_r = F (B + q) / (A (B + q) + q B),
  // and |z_r - z_s| = C gives |A B + q (A + B)| = |F B| / C: a quadratic in
  // the real N. A rigid stator is the limit B -> inf: |A + q| = |F| / C.
  const double m = p.rotor_mass_kg, C = p.clearance_m, f = p.friction_coefficient;
  const cd A(p.rotor_stiffness_N_per_m - m * w * w, p.rotor_damping_N_s_per_m * w);
  const cd F = m * p.eccentricity_m * w * w * std::polar(1.0, p.unbalance_phase_rad);
  const bool rigid = p.stator_model == StatorModel::kRigid;
  const cd B =
      rigid ? cd(0.0) : cd(p.stator_stiffness_N_per_m - p.stator_mass_kg * w * w, p.stator_damping_N_s_per_m * w);
  const cd a = rigid ? A : A * B;
  const cd b = rigid ? cd(1.0, f) / C : cd(1.0, f) * (A + B) / C;
  const double r = rigid ? std::abs(F) / C : std::abs(F * B) / C;
  return {a, b, A, B, F, r, rigid};
}

}  // namespace

double full_rub_discriminant_N2(const ModelParameters& p, double w) {
  const FullRubCircle e = full_rub_circle(p, w);
  // |b|^2 N^2 + 2 Re(a conj(b)) N + |a|^2 - r^2 = 0: ((N1 - N2) / 2)^2.
  const double bb = std::norm(e.b), ab = std::real(e.a * std::conj(e.b)) / bb;
  return ab * ab - (std::norm(e.a) - e.r * e.r) / bb;
}

std::vector<FullRub> synchronous_full_rub(const ModelParameters& p, double w) {
  const FullRubCircle e = full_rub_circle(p, w);
  const double C = p.clearance_m, f = p.friction_coefficient;
  const cd &a = e.a, &b = e.b, &A = e.A, &B = e.B, &F = e.F;
  const double r = e.r;
  const bool rigid = e.rigid;
  std::vector<FullRub> out;
  for (const double N : positive_circle_roots(a, b, r)) {
    const cd q = N * cd(1.0, f) / C;
    FullRub s;
    s.normal_force_N = N;
    if (rigid) {
      s.rotor_m = F / (A + q);
      s.stator_m = 0.0;
    } else {
      s.rotor_m = F * (B + q) / (A * (B + q) + q * B);
      s.stator_m = q * s.rotor_m / (B + q);
    }
    out.push_back(s);
  }
  return out;
}

double rub_onset_speed_rad_per_s(const ModelParameters& p) {
  const double g = p.gravity_m_per_s2;
  // Without gravity no sag (also on a support of zero stiffness, which would
  // give 0/0); with gravity on such a support there is no static position.
  auto sag = [g](double m, double k) { return g == 0.0 ? 0.0 : m * g / k; };
  const double sag_rotor = sag(p.rotor_mass_kg, p.rotor_stiffness_N_per_m);
  const double sag_stator =
      p.stator_model == StatorModel::kRigid ? 0.0 : sag(p.stator_mass_kg, p.stator_stiffness_N_per_m);
  if (!std::isfinite(sag_rotor - sag_stator)) return std::numeric_limits<double>::quiet_NaN();
  const double reach = p.clearance_m - std::abs(sag_rotor - sag_stator);
  if (reach <= 0.0) return 0.0;  // in contact at rest
  // |z| = e rho / sqrt((1 - rho)^2 + 4 zeta^2 rho), rho = (w / w_n)^2, rises
  // from 0 to its peak at rho = 1 / (1 - 2 zeta^2) (for zeta^2 < 1/2; beyond,
  // it rises monotonically towards e).
  const double wn = std::sqrt(p.rotor_stiffness_N_per_m / p.rotor_mass_kg);
  const double zeta = p.rotor_damping_N_s_per_m / (2.0 * std::sqrt(p.rotor_stiffness_N_per_m * p.rotor_mass_kg));
  const double w_peak = 2.0 * zeta * zeta < 1.0 ? wn / std::sqrt(1.0 - 2.0 * zeta * zeta) : 1e3 * wn;
  auto gap = [&](double w) { return std::abs(unbalance_response_m(p, w)) - reach; };
  if (gap(w_peak) < 0.0) return std::numeric_limits<double>::infinity();
  std::uintmax_t iterations = 200;
  const auto bracket = boost::math::tools::toms748_solve(gap, 0.0, w_peak, gap(0.0), gap(w_peak),
                                                         boost::math::tools::eps_tolerance<double>(50), iterations);
  return 0.5 * (bracket.first + bracket.second);
}

}  // namespace rotor_rub::core
