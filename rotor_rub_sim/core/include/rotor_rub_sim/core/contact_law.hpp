// The contact law shared by the three methods: a normal coefficient of
// restitution (default 0, plastic) with Coulomb friction.
//
// * Rigid methods (switching, iteration) apply it at touchdown as an impulse:
//   the closing normal velocity v_n becomes -e v_n; the normal impulse is
//   P = m_eff (1 + e) v_n, and friction adds the tangential impulse -f P sgn(v_slide)
//   on the rotor, limited so that it can stop the sliding but never reverse
//   it. Rebounds slower than impact_settle_velocity_m_per_s settle into
//   sustained contact (the end of a Zeno sequence).
// * The penalty method (I) realises the same law with a spring k_c and a
//   damper c_c = 2 zeta sqrt(k_c m_eff) in parallel, the force clamped at zero
//   (no adhesion). zeta follows from the linear spring-dashpot's restitution,
//   e = exp(-zeta pi / sqrt(1 - zeta^2)), i.e. zeta = -ln e / sqrt(pi^2 + ln^2 e),
//   and zeta = 1 (critical) for e = 0. The undamped spring of the paper is
//   e = 1. The clamp makes a critically damped contact leave with
//   exp(-2) = 0.135 of its impact speed, not 0: for impacts at the mm/s
//   speeds of a run-up rub that rebound is far below the clearance's scale
//   (measured in the method comparison, README).
#pragma once

#include <algorithm>
#include <cmath>

#include "rotor_rub_sim/core/model.hpp"

namespace rotor_rub::core {

inline double contact_damping_ratio(double restitution) {
  if (restitution <= 0.0) return 1.0;
  if (restitution >= 1.0) return 0.0;
  const double l = std::log(restitution);
  return -l / std::sqrt(M_PI * M_PI + l * l);
}

inline double contact_damping_N_s_per_m(const JeffcottModel& m) {
  return 2.0 * contact_damping_ratio(m.parameters().restitution) *
         std::sqrt(m.parameters().contact_stiffness_N_per_m * m.effective_mass_kg());
}

struct ImpactResult {
  double normal_impulse_N_s = 0.0;
  double closing_velocity_m_per_s = 0.0;  // v_n before the impact
  bool settles = false;                   // rebound below the settle speed
};

// Applies the impact law to k (velocities change, positions do not). Call
// only with a closing normal velocity (g.normal_velocity_m_per_s > 0).
inline ImpactResult apply_impact(const JeffcottModel& m, const ContactGeometry& g, Kinematics& k) {
  const ModelParameters& p = m.parameters();
  ImpactResult r;
  r.closing_velocity_m_per_s = g.normal_velocity_m_per_s;
  double e = p.restitution;
  if (e * g.normal_velocity_m_per_s < p.impact_settle_velocity_m_per_s) {
    e = 0.0;
    r.settles = true;
  }
  const double inv_m_sum = m.inv_rotor_mass() + m.inv_stator_mass();
  r.normal_impulse_N_s = (1.0 + e) * g.normal_velocity_m_per_s / inv_m_sum;
  Vec2 impulse_on_rotor = -r.normal_impulse_N_s * g.normal;
  if (m.has_friction()) {
    // Tangential impulse opposing sliding, at most what stops it.
    const double stop = std::abs(g.sliding_velocity_m_per_s) / inv_m_sum;
    const double tangential = std::min(p.friction_coefficient * r.normal_impulse_N_s, stop);
    const double s = g.sliding_velocity_m_per_s > 0.0 ? 1.0 : (g.sliding_velocity_m_per_s < 0.0 ? -1.0 : 0.0);
    impulse_on_rotor -= tangential * s * g.tangent;
  }
  k.rotor_vel += impulse_on_rotor * m.inv_rotor_mass();
  k.stator_vel -= impulse_on_rotor * m.inv_stator_mass();
  return r;
}

}  // namespace rotor_rub::core
