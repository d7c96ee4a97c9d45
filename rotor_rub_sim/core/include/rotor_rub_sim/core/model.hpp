// The Jeffcott rotor with an elastically supported stator (Hynek 2002, eq. 2.1),
// shared by all three contact methods. A method decides only the contact's
// normal force; everything else is here.
//
// Modelling choices (SI units throughout):
// * Coordinates: inertial x, y; the rotor's geometric centre r_r = (x_r, y_r)
//   and the stator's centre r_s = (x_s, y_s). Spin is counter-clockwise
//   positive.
// * Unbalance: the mass centre sits at r_r + e (cos phi, sin phi), phi the spin
//   angle. Newton's law for the mass centre, with the shaft's spring and damper
//   acting at the geometric centre, gives
//     m_r r_r'' + b_r r_r' + k_r r_r = m_r e w^2 (cos phi, sin phi)
//                                    + m_r e A (sin phi, -cos phi) + F_contact,
//   i.e. the tangential term LAGS the unbalance by 90 deg under acceleration
//   A > 0. The paper's eq. (2.2) writes +m_r e A on its rotating axis y_3; we
//   follow the kinematics. The term is small (m e A = 0.012 N against
//   m e w^2 = 1.7 N at 100 rad/s in the paper scene).
// * Drive: the speed is prescribed (speed_profile.hpp); no torsional DOF.
// * Gravity: none unless the scene sets gravity_m_per_s2 (acts along -y on
//   rotor and stator).
// * Stator offset: the stator's springs pull it to (stator_offset_x_m,
//   stator_offset_y_m), where a rigid stator sits (a misaligned casing);
//   the shaft's spring centre is the casing's origin, where the rotor starts.
// * Stator: mass m_s on springs k_s and dampers b_s (elastic), or immovable
//   (rigid, then the state holds the rotor's 2 DOF only).
// * Contact geometry: delta = |r_r - r_s|, outward normal n = (r_r - r_s)/delta,
//   tangent t = n rotated +90 deg. Penetration is delta - C.
// * Normal force F_n >= 0 pushes the rotor by -F_n n and the stator by +F_n n.
// * Friction: Coulomb with stick and slip. The sliding velocity of the
//   rotor's surface over the stator's at the contact point is
//     v_slide = (r_r' - r_s') . t + w R_r
//   (the stator does not spin). The tangential force on the rotor is F_t t
//   (the stator gets -F_t t, Newton's third law), with |F_t| <= f F_n:
//   sliding, F_t = -f F_n sgn(v_slide); sticking (rolling, v_slide = 0), F_t
//   is whatever holds v_slide = 0, as long as it stays in the cone. How a
//   method realises that is its own business (contact_law.hpp): the rigid
//   methods locate v_slide = 0 and switch between slip and stick exactly; the
//   penalty method caps a tangential damper at f F_n.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"

namespace rotor_rub::core {

using Vec2 = Eigen::Vector2d;

// Layout of the free (unconstrained) state vector. kStatorDof is 2 for an
// elastic stator and 0 for a rigid one.
template <int kStatorDof>
struct FreeLayout {
  static_assert(kStatorDof == 0 || kStatorDof == 2, "stator has 0 or 2 DOF");
  static constexpr int kDof = 2 + kStatorDof;
  static constexpr int kSize = 2 * kDof;
  static constexpr int kRotorPos = 0;          // x_r, y_r [m]
  static constexpr int kStatorPos = 2;         // x_s, y_s [m] (elastic only)
  static constexpr int kRotorVel = kDof;       // x_r', y_r' [m/s]
  static constexpr int kStatorVel = kDof + 2;  // x_s', y_s' [m/s] (elastic only)
  using State = Eigen::Matrix<double, kSize, 1>;
};

// Positions and velocities of both bodies as plain 2-vectors (a rigid stator
// is at rest at the origin).
struct Kinematics {
  Vec2 rotor_pos = Vec2::Zero();
  Vec2 rotor_vel = Vec2::Zero();
  Vec2 stator_pos = Vec2::Zero();
  Vec2 stator_vel = Vec2::Zero();
};

template <int kStatorDof>
Kinematics kinematics_of(const typename FreeLayout<kStatorDof>::State& x) {
  using L = FreeLayout<kStatorDof>;
  Kinematics k;
  k.rotor_pos = x.template segment<2>(L::kRotorPos);
  k.rotor_vel = x.template segment<2>(L::kRotorVel);
  if constexpr (kStatorDof == 2) {
    k.stator_pos = x.template segment<2>(L::kStatorPos);
    k.stator_vel = x.template segment<2>(L::kStatorVel);
  }
  return k;
}

template <int kStatorDof>
void store_kinematics(const Kinematics& k, typename FreeLayout<kStatorDof>::State& x) {
  using L = FreeLayout<kStatorDof>;
  x.template segment<2>(L::kRotorPos) = k.rotor_pos;
  x.template segment<2>(L::kRotorVel) = k.rotor_vel;
  if constexpr (kStatorDof == 2) {
    x.template segment<2>(L::kStatorPos) = k.stator_pos;
    x.template segment<2>(L::kStatorVel) = k.stator_vel;
  }
}

struct ContactGeometry {
  double distance_m = 0.0;                // delta = |r_r - r_s|
  double penetration_m = 0.0;             // delta - C (> 0: rotor beyond the clearance)
  double normal_velocity_m_per_s = 0.0;   // delta' (> 0: closing into the stator)
  double sliding_velocity_m_per_s = 0.0;  // v_slide (see the header comment)
  Vec2 normal = Vec2::UnitX();            // n, outward from the stator's centre
  Vec2 tangent = Vec2::UnitY();           // t = n rotated +90 deg
};

class JeffcottModel {
 public:
  explicit JeffcottModel(const ModelParameters& p)
      : p_(p),
        inv_rotor_mass_(1.0 / p.rotor_mass_kg),
        inv_stator_mass_(p.stator_model == StatorModel::kRigid ? 0.0 : 1.0 / p.stator_mass_kg),
        effective_mass_kg_(1.0 / (inv_rotor_mass_ + inv_stator_mass_)),
        has_friction_(p.friction_coefficient > 0.0),
        stator_offset_(p.stator_offset_x_m, p.stator_offset_y_m) {
    // A rigid stator has no state: the methods work in its frame (its centre
    // at the origin), where the shaft's spring centre is -offset; samples are
    // shifted back by +offset (frame_shift()). An elastic stator's springs pull
    // it to the offset; the frame is the casing's.
    const bool rigid = p.stator_model == StatorModel::kRigid;
    rotor_spring_centre_ = rigid ? Vec2(-stator_offset_) : Vec2::Zero();
    stator_spring_centre_ = rigid ? Vec2::Zero() : stator_offset_;
    frame_shift_ = rigid ? stator_offset_ : Vec2::Zero();
  }

  // Where the methods start (t = 0): at rest, the rotor centred in the casing,
  // the stator at its rest position; in the methods' frame.
  Kinematics initial_kinematics() const {
    Kinematics k;
    k.rotor_pos = Vec2::Zero() - frame_shift_;  // +0, not -0, without an offset
    k.stator_pos = stator_spring_centre_;
    return k;
  }
  // Methods' frame -> the casing's (what samples report): add this to positions.
  const Vec2& frame_shift() const { return frame_shift_; }

  const ModelParameters& parameters() const { return p_; }
  double inv_rotor_mass() const { return inv_rotor_mass_; }
  double inv_stator_mass() const { return inv_stator_mass_; }
  // m_r m_s / (m_r + m_s): the mass the contact sees (m_r for a rigid stator).
  double effective_mass_kg() const { return effective_mass_kg_; }
  bool has_friction() const { return has_friction_; }

  // All forces on the rotor except contact: shaft spring and damper,
  // unbalance, gravity [N].
  Vec2 rotor_free_force(const Kinematics& k, const DriveState& d) const {
    const double me = p_.rotor_mass_kg * p_.eccentricity_m;
    const double c = std::cos(d.angle_rad), s = std::sin(d.angle_rad);
    const double w2 = d.speed_rad_per_s * d.speed_rad_per_s;
    Vec2 f =
        -p_.rotor_stiffness_N_per_m * (k.rotor_pos - rotor_spring_centre_) - p_.rotor_damping_N_s_per_m * k.rotor_vel;
    f.x() += me * (w2 * c + d.accel_rad_per_s2 * s);
    f.y() += me * (w2 * s - d.accel_rad_per_s2 * c) - p_.rotor_mass_kg * p_.gravity_m_per_s2;
    return f;
  }

  // All forces on the stator except contact [N] (zero for a rigid stator,
  // whose acceleration is zero anyway).
  Vec2 stator_free_force(const Kinematics& k) const {
    if (p_.stator_model == StatorModel::kRigid) return Vec2::Zero();
    Vec2 f = -p_.stator_stiffness_N_per_m * (k.stator_pos - stator_spring_centre_) -
             p_.stator_damping_N_s_per_m * k.stator_vel;
    f.y() -= p_.stator_mass_kg * p_.gravity_m_per_s2;
    return f;
  }

  ContactGeometry contact_geometry(const Kinematics& k, const DriveState& d) const {
    ContactGeometry g;
    const Vec2 rel = k.rotor_pos - k.stator_pos;
    g.distance_m = rel.norm();
    // The normal is undefined only with the rotor exactly centred, far from
    // any contact; any unit vector then does.
    if (g.distance_m > 0.0) g.normal = rel / g.distance_m;
    g.tangent = Vec2(-g.normal.y(), g.normal.x());
    g.penetration_m = g.distance_m - p_.clearance_m;
    const Vec2 rel_vel = k.rotor_vel - k.stator_vel;
    g.normal_velocity_m_per_s = rel_vel.dot(g.normal);
    g.sliding_velocity_m_per_s = rel_vel.dot(g.tangent) + d.speed_rad_per_s * p_.rotor_radius_m;
    return g;
  }

  // The contact force on the rotor for normal force F_n >= 0 and tangential
  // force F_t along t [N] (the stator gets the opposite).
  static Vec2 contact_force_on_rotor(const ContactGeometry& g, double normal_force_N, double tangential_force_N) {
    return -normal_force_N * g.normal + tangential_force_N * g.tangent;
  }

  // Accelerations of rotor and stator under given contact forces [m/s^2].
  void accelerations(const Kinematics& k, const DriveState& d, const ContactGeometry& g, double normal_force_N,
                     double tangential_force_N, Vec2& rotor_acc, Vec2& stator_acc) const {
    const Vec2 on_rotor = contact_force_on_rotor(g, normal_force_N, tangential_force_N);
    rotor_acc = (rotor_free_force(k, d) + on_rotor) * inv_rotor_mass_;
    stator_acc = (stator_free_force(k) - on_rotor) * inv_stator_mass_;
  }

  // Second time derivative of delta for given accelerations:
  // delta'' = n . (a_r - a_s) + |v_rel . t|^2 / delta.
  static double distance_acceleration(const Kinematics& k, const ContactGeometry& g, const Vec2& rotor_acc,
                                      const Vec2& stator_acc) {
    const double vt = (k.rotor_vel - k.stator_vel).dot(g.tangent);
    return g.normal.dot(rotor_acc - stator_acc) + vt * vt / g.distance_m;
  }

  // Time derivative of v_slide for given accelerations:
  // v_slide' = t . (a_r - a_s) - (v_rel . n)(v_rel . t) / delta + A R_r.
  double sliding_acceleration(const Kinematics& k, const DriveState& d, const ContactGeometry& g, const Vec2& rotor_acc,
                              const Vec2& stator_acc) const {
    const Vec2 v = k.rotor_vel - k.stator_vel;
    return g.tangent.dot(rotor_acc - stator_acc) - v.dot(g.normal) * v.dot(g.tangent) / g.distance_m +
           d.accel_rad_per_s2 * p_.rotor_radius_m;
  }

 private:
  ModelParameters p_;
  double inv_rotor_mass_;
  double inv_stator_mass_;
  double effective_mass_kg_;
  bool has_friction_;
  Vec2 stator_offset_, rotor_spring_centre_, stator_spring_centre_, frame_shift_;
};

}  // namespace rotor_rub::core
