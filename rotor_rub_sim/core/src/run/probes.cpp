#include "rotor_rub_sim/core/probes.hpp"

#include <cmath>

namespace rotor_rub::core {

ProbePair::ProbePair(const ProbeParameters& p) : p_(p), rng_(static_cast<std::uint64_t>(p.noise_seed)) {}

ProbeReading ProbePair::read(const Sample& s) {
  const double phi = s.drive.angle_rad + p_.runout_phase_rad;
  const Vec2 seen = s.probe_displacement_m + p_.runout_m * Vec2(std::cos(phi), std::sin(phi));
  ProbeReading r;
  r.t_s = s.t_s;
  r.x_m = seen.dot(Vec2(std::cos(p_.x_angle_rad), std::sin(p_.x_angle_rad)));
  r.y_m = seen.dot(Vec2(std::cos(p_.y_angle_rad), std::sin(p_.y_angle_rad)));
  r.x_V = p_.sensitivity_V_per_m * r.x_m;
  r.y_V = p_.sensitivity_V_per_m * r.y_m;
  if (p_.noise_V > 0.0) {
    r.x_V += p_.noise_V * noise_(rng_);
    r.y_V += p_.noise_V * noise_(rng_);
  }
  return r;
}

}  // namespace rotor_rub::core
