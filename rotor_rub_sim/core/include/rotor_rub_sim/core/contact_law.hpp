// The contact law shared by the three methods: a normal coefficient of
// restitution e (default 0, plastic) with Coulomb friction in stick and slip.
//
// Rigid methods (switching, iteration):
// * Touchdown is an impact: the closing normal velocity v_n becomes -e v_n;
//   the normal impulse is P = m_eff (1 + e) v_n (m_eff = m_r m_s/(m_r + m_s),
//   m_r for a rigid stator), equal and opposite on rotor and stator. Friction
//   adds the tangential impulse -f P sgn(v_slide) on the rotor, limited so that
//   it can stop the sliding but never reverse it (then the contact starts in
//   stick if the cone allows).
// * A rebound settles into sustained contact (plastic, e taken as 0) when its
//   flight could not leave the bore by more than the position tolerance: the
//   apex (e v_n)^2 / (2 a_press), a_press the normal acceleration that presses
//   the rotor onto the bore without contact force, is below
//   settle_apex_m (the run's atol), or the rebound is slower than
//   impact_settle_velocity_m_per_s. This ends a Zeno sequence of ever smaller
//   bounces at its accumulation point, with a position error below atol.
// * In sustained contact, slip: F_t = -f F_n s with s = sgn(v_slide) held
//   fixed until v_slide crosses 0 (located as an event); stick (rolling):
//   F_t is the constraint force that holds v_slide = 0, kept while
//   |F_t| <= f F_n (the crossing located as an event). At v_slide = 0 the
//   contact sticks if the stick force is inside the cone, else it slides in
//   the direction s = -sgn(F_t,stick) (select_friction_mode()).
//
// Penalty method (I): the same law, regularised.
// * Normal: spring k_c and damper c_c = 2 zeta sqrt(k_c m_eff) in parallel,
//   the force clamped at zero (no adhesion: the contact ends when the force,
//   not the penetration, returns to zero). For this clamped law the rebound
//   ratio has a closed form (derived in docs/contact_law.md):
//     zeta < 1:  e = exp(-q (pi - 2 atan q)),   q = zeta / sqrt(1 - zeta^2)
//     zeta = 1:  e = exp(-2)
//     zeta > 1:  e = exp(-p ln((p + 1)/(p - 1))), p = zeta / sqrt(zeta^2 - 1)
//   and contact_damping_ratio() inverts it, so penalty impacts rebound with
//   the scene's e. e -> 0 needs zeta -> infinity (e ~ 1/(4 zeta^2)); below
//   penalty_restitution_floor(k_c) (0.01 up to k_c 1e9, lower above) the
//   penalty method uses the floor (documented in docs/contact_law.md with its
//   cost and its error).
// * Tangential: a damper capped at the cone, F_t = -clamp(c_t v_slide,
//   -f F_n, f F_n) with c_t = 2 sqrt(k_c m_eff), the contact's critical
//   damping. Its rate c_t / m_eff = 2 omega_c is of the contact's own order
//   (below the normal damper's 9.5 omega_c at e = 0; it sets RK4's bound for
//   e >= 0.1, rk4_stability.hpp), so rolling never stalls the integrator;
//   in stick the surfaces creep at |F_t| / c_t, which vanishes as k_c grows.
#pragma once

#include <algorithm>
#include <boost/math/tools/roots.hpp>
#include <cmath>
#include <cstdint>
#include <limits>

#include "rotor_rub_sim/core/model.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

// ---- Penalty: the clamped spring-dashpot ----------------------------------

// Rebound ratio of the clamped linear spring-dashpot at damping ratio zeta.
inline double clamped_dashpot_restitution(double zeta) {
  if (zeta <= 0.0) return 1.0;
  if (zeta < 1.0) {
    const double q = zeta / std::sqrt(1.0 - zeta * zeta);
    return std::exp(-q * (M_PI - 2.0 * std::atan(q)));
  }
  if (zeta == 1.0) return std::exp(-2.0);
  const double p = zeta / std::sqrt(zeta * zeta - 1.0);
  return std::exp(-p * std::log((p + 1.0) / (p - 1.0)));
}

// The penalty method's restitution floor: e -> 0 needs an infinite damper.
// At 0.01 (zeta = 4.81) the rebound of a 10 mm/s impact is 0.1 mm/s; the
// damper's rate 2 zeta omega_c sets the explicit step in contact. Up to
// k_c = 1e9 the floor is 0.01; stiffer contacts get a lower one,
// 0.01 sqrt(1e9 / k_c), so that the floor's rebound keeps shrinking with the
// compliance and the penalty method keeps converging to the rigid methods as
// k_c grows (a fixed 0.01 stopped it at ~2e-6 m on the paper scene).
inline constexpr double kPenaltyRestitutionFloor = 0.01;
inline constexpr double kPenaltyFloorStiffness_N_per_m = 1e9;
inline double penalty_restitution_floor(double contact_stiffness_N_per_m) {
  if (!(contact_stiffness_N_per_m > kPenaltyFloorStiffness_N_per_m)) return kPenaltyRestitutionFloor;
  return kPenaltyRestitutionFloor * std::sqrt(kPenaltyFloorStiffness_N_per_m / contact_stiffness_N_per_m);
}

// The damping ratio whose clamped law rebounds with max(e, floor).
inline double contact_damping_ratio(double restitution, double floor = kPenaltyRestitutionFloor) {
  const double e = std::max(restitution, floor);
  if (e >= 1.0) return 0.0;
  auto f = [e](double zeta) { return clamped_dashpot_restitution(zeta) - e; };
  std::uintmax_t it = 200;
  auto tol = [](double a, double b) { return std::abs(b - a) <= 1e-14 * std::abs(b); };
  // e(zeta) falls monotonically from 1 at 0 to ~1/(4 zeta^2): [0, 1e4]
  // brackets every e >= 1e-8.
  const auto br = boost::math::tools::toms748_solve(f, 0.0, 1e4, tol, it);
  return 0.5 * (br.first + br.second);
}

// The penalty method's damping ratio for a scene (restitution and k_c).
inline double contact_damping_ratio(const ModelParameters& p) {
  return contact_damping_ratio(p.restitution, penalty_restitution_floor(p.contact_stiffness_N_per_m));
}

// The penalty damper c_c [N s/m]: the scene's contact_damping_N_s_per_m
// where given, else 2 zeta sqrt(k_c m_eff) with zeta from the restitution.
inline double contact_damping_N_s_per_m(const StationModel& m) {
  const ModelParameters& p = m.parameters();
  if (p.contact_damping_N_s_per_m > 0.0) return p.contact_damping_N_s_per_m;
  return 2.0 * contact_damping_ratio(p) * std::sqrt(p.contact_stiffness_N_per_m * m.effective_mass_kg());
}

// The same as a damping ratio of the contact mode, c_c / (2 sqrt(k_c m_eff)).
inline double contact_damping_ratio(const StationModel& m) {
  return contact_damping_N_s_per_m(m) /
         (2.0 * std::sqrt(m.parameters().contact_stiffness_N_per_m * m.effective_mass_kg()));
}

// The tangential damper of the penalty friction [N s/m].
inline double tangential_damping_N_s_per_m(const StationModel& m) {
  return 2.0 * std::sqrt(m.parameters().contact_stiffness_N_per_m * m.effective_mass_kg());
}

// The penalty friction force on the rotor along t [N].
inline double penalty_friction_N(double friction_coefficient, double normal_force_N, double tangential_damping,
                                 double sliding_velocity_m_per_s) {
  const double cap = friction_coefficient * normal_force_N;
  return -std::clamp(tangential_damping * sliding_velocity_m_per_s, -cap, cap);
}

// ---- Rigid methods: impact, settling, stick and slip -----------------------

// Whether the rotor closes on the bore at a located gap crossing: v_n above
// the rounding of the state's velocities. A lift-off leaves the two bodies
// with v_n = 0 to about 1e-16 of their speeds (the projection), and right
// after it the gap opens as the cube of the time, below its own rounding for
// microseconds: its sign can flip back with v_n = 0 or 7e-18 m/s (other last
// bits, 6e-11 s after a lift-off). kClosingRounding is 1e-12 of the speeds
// (4500 epsilon); a rebound cascade's slowest grazes close at 1e-6 m/s.
inline constexpr double kClosingRounding = 1e-12;
inline bool closes(const ContactGeometry& g, const Kinematics& k) {
  return g.normal_velocity_m_per_s > kClosingRounding * (k.rotor_vel.norm() + k.stator_vel.norm());
}
// Whether the rotor leaves the bore: v_n below minus that rounding.
inline bool opens(const ContactGeometry& g, const Kinematics& k) {
  return g.normal_velocity_m_per_s < -kClosingRounding * (k.rotor_vel.norm() + k.stator_vel.norm());
}

// |phi' - psi'| [rad/s]: how fast the unbalance turns in the contact frame,
// the spin less the whirl of the rotor about the stator (the rigid methods
// bound a held step's scan interval by it: event_scanner.hpp).
inline double forcing_rate_rad_per_s(const Kinematics& k, const DriveState& d, const ContactGeometry& g) {
  return std::abs(d.speed_rad_per_s - (k.rotor_vel - k.stator_vel).dot(g.tangent) / g.distance_m);
}

struct ImpactResult {
  double normal_impulse_N_s = 0.0;
  double closing_velocity_m_per_s = 0.0;  // v_n before the impact
  bool settles = false;                   // plastic: sustained contact follows if pressed
  bool sliding_stopped = false;           // the tangential impulse stopped the sliding
  double spin_jump_rad_per_s = 0.0;       // a motor's spin speed change (a flexible rotor's modes take a share)
};

// The normal acceleration of delta without contact force [m/s^2]: > 0 when
// the free motion presses the rotor onto the bore.
inline double pressing_acceleration(const JeffcottModel& m, const Kinematics& k, const DriveState& d,
                                    const ContactGeometry& g) {
  return JeffcottModel::distance_acceleration(k, g, m.accelerations(k, d, g, 0.0, 0.0));
}
// The same from the state's free loads (a flexible rotor's station force
// holds its modal coordinates, which k does not).
inline double pressing_acceleration(const StationModel& m, const Kinematics& k, const DriveState& d,
                                    const ContactGeometry& g, const FreeLoads& free) {
  return StationModel::distance_acceleration(k, g, m.accelerations(d, g, free, 0.0, 0.0));
}

// The impact law when the spin takes part (a motor drive): the tangential
// impulse P_t acts on the spin through R_r and the normal one through the
// unbalance's lever, so normal and tangential velocities answer both
// impulses through the compliance W (model.hpp): d(v_n, v_slide) =
// W (-dP_n, dP_t). The impact is followed along its normal impulse P_n
// (Darboux and Keller), with the friction of the sliding at each instant:
// * sliding (s = sgn v_slide), dP_t = -f s dP_n: v_n falls at the rate
//   W_nn + f s W_nt, v_slide at W_nt + f s W_tt (per unit P_n);
// * where v_slide reaches 0 the contact sticks on, dP_t = (W_nt / W_tt) dP_n,
//   if that ratio lies in the cone (|W_nt| <= f W_tt), else it slides the
//   other way, s' = -sgn W_nt (the coupling W_nt drives v_slide through 0);
// * the impact ends where v_n reaches -e v_n (Newton's law, as without the
//   spin). W is constant through the impact (positions do not move), so the
//   path is piecewise linear in P_n and exact in closed form.
// With W_nt = 0 and W_tt = W_nn = 1/m_eff this is the prescribed drive's law
// below. W_nn + f s W_nt <= 0 (Painleve's paradox: the friction would pull
// the bodies together faster than the normal impulse parts them) cannot
// occur for either s while J_G > f e (R_r + e) m_r, which validate_scene()
// demands (a flexible rotor's counterpart: validate_flexible_spin); the
// check below is the guard behind it.
// sc: the state's spin coupling (FreeLoads::spin).
inline ImpactResult apply_impact_with_spin(const StationModel& m, const ContactGeometry& g, const SpinCoupling& sc,
                                           double e, ImpactResult r, Kinematics& k) {
  const ModelParameters& p = m.parameters();
  const ContactCompliance w = m.contact_compliance(g, sc);
  const double f = m.has_friction() ? p.friction_coefficient : 0.0;
  const double target_vn = -e * g.normal_velocity_m_per_s;
  double vn = g.normal_velocity_m_per_s, vs = g.sliding_velocity_m_per_s;
  double pn = 0.0, pt = 0.0;
  auto sign = [](double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); };
  // Two pieces at most: a slide, then a stick or a slide back (which never
  // stops); the bound is a guard.
  for (int piece = 0; piece < 3 && vn > target_vn; ++piece) {
    double ratio;  // dP_t / dP_n
    const double s = sign(vs);
    const bool stick = f > 0.0 && s == 0.0 && std::abs(w.nt) <= f * w.tt;
    if (f == 0.0) {
      ratio = 0.0;
    } else if (s != 0.0) {
      ratio = -f * s;
    } else if (stick) {
      ratio = w.nt / w.tt;
    } else {
      ratio = f * sign(w.nt);  // sliding in s' = -sgn W_nt
    }
    const double vn_rate = w.nn - ratio * w.nt;  // -dv_n / dP_n
    const double vs_rate = w.nt - ratio * w.tt;  // -dv_slide / dP_n
    if (!(vn_rate > 0.0)) {
      throw MethodFailure(FailureClass::kInvariantViolated, std::numeric_limits<double>::quiet_NaN(),
                          "impact: W_nn + f s W_nt <= 0 (Painleve's paradox; lower friction_coefficient, or raise "
                          "rotor_polar_inertia_kg_m2)");
    }
    double dp = (vn - target_vn) / vn_rate;
    // A slide that v_slide's own rate brings to rest inside the impact.
    const bool stops = s != 0.0 && f > 0.0 && s * vs_rate > 0.0 && vs / vs_rate <= dp;
    if (stops) dp = vs / vs_rate;
    pn += dp;
    pt += ratio * dp;
    vn -= vn_rate * dp;
    // Held at exactly 0 in a stick (vs_rate is 0 there but for a rounding).
    vs = stops || stick ? 0.0 : vs - vs_rate * dp;
    if (stops) vn = std::max(vn, target_vn);  // rounding at a stop that coincides with the end
  }
  r.sliding_stopped = f > 0.0 && vs == 0.0;
  r.normal_impulse_N_s = pn;
  r.spin_jump_rad_per_s = m.apply_impulse(g, pn, pt, sc, k);
  return r;
}

// Applies the impact law to k (velocities change, positions do not). Call
// only with a closing normal velocity (g.normal_velocity_m_per_s > 0).
// settle_apex_m: a rebound whose flight apex would stay below it settles.
// free: the state's free loads (model.hpp; a flexible rotor's from its
// model), which decide whether a slow rebound settles.
inline ImpactResult apply_impact(const StationModel& m, const ContactGeometry& g, const DriveState& d,
                                 double settle_apex_m, const FreeLoads& free, Kinematics& k) {
  const ModelParameters& p = m.parameters();
  ImpactResult r;
  r.closing_velocity_m_per_s = g.normal_velocity_m_per_s;
  double e = p.restitution;
  const double rebound = e * g.normal_velocity_m_per_s;
  const double a_press = pressing_acceleration(m, k, d, g, free);
  if (rebound < p.impact_settle_velocity_m_per_s ||
      (a_press > 0.0 && rebound * rebound <= 2.0 * a_press * settle_apex_m)) {
    e = 0.0;
    r.settles = true;
  }
  if (m.motor()) return apply_impact_with_spin(m, g, free.spin, e, r, k);
  const double inv_m_sum = m.inv_rotor_mass() + m.inv_stator_mass();
  r.normal_impulse_N_s = (1.0 + e) * g.normal_velocity_m_per_s / inv_m_sum;
  Vec2 impulse_on_rotor = -r.normal_impulse_N_s * g.normal;
  if (m.has_friction()) {
    // Tangential impulse opposing sliding, at most what stops it.
    const double stop = std::abs(g.sliding_velocity_m_per_s) / inv_m_sum;
    const double limit = p.friction_coefficient * r.normal_impulse_N_s;
    r.sliding_stopped = stop <= limit;
    const double tangential = std::min(limit, stop);
    const double s = g.sliding_velocity_m_per_s > 0.0 ? 1.0 : (g.sliding_velocity_m_per_s < 0.0 ? -1.0 : 0.0);
    impulse_on_rotor -= tangential * s * g.tangent;
  }
  k.rotor_vel += impulse_on_rotor * m.inv_rotor_mass();
  k.stator_vel -= impulse_on_rotor * m.inv_stator_mass();
  return r;
}

// The same for the Jeffcott, whose free loads follow from k.
inline ImpactResult apply_impact(const JeffcottModel& m, const ContactGeometry& g, const DriveState& d,
                                 double settle_apex_m, Kinematics& k) {
  return apply_impact(m, g, d, settle_apex_m, m.free_loads(k, d), k);
}

// The friction regime of a sustained contact. slip_sign s is sgn(v_slide)
// while sliding (the friction on the rotor is -f F_n s).
struct FrictionMode {
  bool stick = false;
  double slip_sign = 1.0;
};

// The friction regime at v_slide (at_rest: v_slide is zero to the event's
// resolution) given the force that would hold v_slide = 0 and the cone f F_n.
inline FrictionMode select_friction_mode(double sliding_velocity_m_per_s, bool at_rest, double stick_force_N,
                                         double cone_N) {
  FrictionMode mode;
  if (!at_rest) {
    mode.slip_sign = sliding_velocity_m_per_s >= 0.0 ? 1.0 : -1.0;
    return mode;
  }
  // Without friction (cone 0) there is no stick: the contact slides freely.
  if (cone_N > 0.0 && std::abs(stick_force_N) <= cone_N) {
    mode.stick = true;
    return mode;
  }
  mode.slip_sign = stick_force_N > 0.0 ? -1.0 : 1.0;
  return mode;
}

}  // namespace rotor_rub::core
