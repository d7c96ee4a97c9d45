// The Jeffcott rotor with an elastically supported stator (Hynek 2002, eq. 2.1),
// shared by all three contact methods: the rub station and the stator
// (StationModel, which every rotor model shares: rotor_model.hpp) and the
// Jeffcott's shaft and unbalance on it (JeffcottModel). A method decides only
// the contact's forces; everything else is here.
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
// * Drive, prescribed (the default, the paper's): the speed profile is the
//   spin (speed_profile.hpp); no torsional DOF. The torque such an ideal
//   drive applies is reported (drive_torque below), never fed back.
// * Drive, motor (drive_model motor): the spin angle phi and speed w are
//   states. Lagrange's equations for the coordinates (x_r, y_r, phi) of a
//   rotor whose mass centre is r_r + e (cos phi, sin phi) give, with
//   u = (sin phi, -cos phi) and F the forces at the geometric centre (shaft
//   spring and damper, contact force), T_m the motor torque and R_r F_t the
//   friction's torque (the tangential force acts at the contact point
//   r_r + R_r n, whose virtual displacement is dr_r + R_r dphi t):
//     J_G phi'' = T_m + R_r F_t + e F . u          (gravity has no torque about G)
//     m_r r_r'' = F + m_r e (w^2 (cos phi, sin phi) + phi'' u) - m_r g y
//   J_G the polar inertia about the mass centre (J_G + m e^2 about the shaft
//   axis). The coupling e F . u is the unbalance's reaction on the spin (the
//   Sommerfeld effect): with it, the motor's work pays every loss, which the
//   power balance test checks. The motor: T_m = clamp(J_G A_ref + K_p
//   (w_ref - w) + K_i z, -T_max, T_max), its integrator z' = (w_ref - w) +
//   (T_m - T_cmd) / K_p (back-calculation anti-windup: in saturation z
//   relaxes to (T_max - J_G A_ref) / K_i instead of winding up),
//   w_ref, A_ref the speed profile's speed and acceleration.
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

#include <cmath>

#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"
#include "rotor_rub_sim/core/state_layout.hpp"
#include "rotor_rub_sim/core/station_model.hpp"

namespace rotor_rub::core {

// The paper's Jeffcott rotor on its station: the shaft's spring k_r and
// damper b_r about the casing's centre and the unbalance m_r e (the header
// comment's equations); JeffcottRotor (rotor_model.hpp) gives the methods its
// free loads.
class JeffcottModel : public StationModel {
 public:
  explicit JeffcottModel(const ModelParameters& p)
      : StationModel(p),
        inv_polar_inertia_(1.0 / p.rotor_polar_inertia_kg_m2),
        // The shaft's spring centre is the casing's origin: -offset in a
        // rigid stator's frame.
        rotor_spring_centre_(p.stator_model == StatorModel::kRigid ? Vec2(-stator_offset_) : Vec2::Zero()) {}
  using StationModel::accelerations;
  using StationModel::apply_impulse;
  using StationModel::contact_compliance;

  // e F . u, the unbalance's lever torque on the spin that the prescribed
  // drive supplies besides J A - R_r F_t (station_drive_torque_N_m), for
  // kinematics in the casing's frame (a sample's: the shaft's spring centre
  // at the origin), the unbalance's direction dir at the spin angle
  // (unbalance_dir) and the contact force on the rotor [N m].
  double unbalance_torque_N_m(const Kinematics& casing, const Vec2& dir, const Vec2& contact_force_N) const {
    const Vec2 u(dir.y(), -dir.x());
    const Vec2 shaft = -p_.rotor_stiffness_N_per_m * casing.rotor_pos - p_.rotor_damping_N_s_per_m * casing.rotor_vel;
    return p_.eccentricity_m * (shaft + contact_force_N).dot(u);
  }
  // The shaft's spring and damper on the rotor [N].
  Vec2 shaft_force(const Kinematics& k) const {
    return -p_.rotor_stiffness_N_per_m * (k.rotor_pos - rotor_spring_centre_) -
           p_.rotor_damping_N_s_per_m * k.rotor_vel;
  }

  // All forces on the rotor except contact: shaft spring and damper,
  // unbalance, gravity [N], for the spin acceleration d.accel_rad_per_s2 (the
  // prescribed drive's; a motor's depends on the contact forces:
  // accelerations()).
  Vec2 rotor_free_force(const Kinematics& k, const DriveState& d) const {
    return rotor_free_force(k, d, unbalance_dir(d.angle_rad));
  }
  // The same, given the unbalance's direction (cos phi, sin phi) of d.angle_rad.
  Vec2 rotor_free_force(const Kinematics& k, const DriveState& d, const Vec2& unbalance_dir) const {
    const double me = p_.rotor_mass_kg * p_.eccentricity_m;
    const double c = unbalance_dir.x(), s = unbalance_dir.y();
    const double w2 = d.speed_rad_per_s * d.speed_rad_per_s;
    // Written per component and packed once at the end: a lane written to
    // memory and the pair read back stalls the store forwarding. Same sums,
    // same bits as
    // f = -k_r (r_r - c) - b_r r_r', f.y += ...
    const double kr = -p_.rotor_stiffness_N_per_m, br = p_.rotor_damping_N_s_per_m;
    const double fx = (kr * (k.rotor_pos.x() - rotor_spring_centre_.x()) - br * k.rotor_vel.x()) +
                      me * (w2 * c + d.accel_rad_per_s2 * s);
    const double fy = (kr * (k.rotor_pos.y() - rotor_spring_centre_.y()) - br * k.rotor_vel.y()) +
                      (me * (w2 * s - d.accel_rad_per_s2 * c) - p_.rotor_mass_kg * p_.gravity_m_per_s2);
    return Vec2(fx, fy);
  }

  // The free forces are linear in the state (a closed-form Jacobian,
  // penalty_system.hpp): d F_r = -k_r d r_r - b_r d r_r', the stator's alike
  // (zero for a rigid stator, which has no state) [N/m, N s/m].
  struct FreeForceGains {
    double rotor_stiffness_N_per_m, rotor_damping_N_s_per_m, stator_stiffness_N_per_m, stator_damping_N_s_per_m;
  };
  FreeForceGains free_force_gains() const {
    const bool rigid = p_.stator_model == StatorModel::kRigid;
    return {p_.rotor_stiffness_N_per_m, p_.rotor_damping_N_s_per_m, rigid ? 0.0 : p_.stator_stiffness_N_per_m,
            rigid ? 0.0 : p_.stator_damping_N_s_per_m};
  }

  // The partial time derivative of rotor_free_force at a fixed state under
  // the prescribed drive d, whose acceleration A is constant on a speed
  // segment [N/s]: the unbalance m e (w^2 (c, s) + A (s, -c)) turning with
  // phi' = w, w' = A gives m e (3 w A (c, s) + w^3 (-s, c)).
  Vec2 rotor_free_force_rate(const DriveState& d) const { return rotor_free_force_rate(d, unbalance_dir(d.angle_rad)); }
  // The same, given the unbalance's direction (cos phi, sin phi) of d.angle_rad.
  Vec2 rotor_free_force_rate(const DriveState& d, const Vec2& unbalance_dir) const {
    const double me = p_.rotor_mass_kg * p_.eccentricity_m;
    const double c = unbalance_dir.x(), s = unbalance_dir.y();
    const double w = d.speed_rad_per_s, a3 = 3.0 * w * d.accel_rad_per_s2, w3 = w * w * w;
    return me * Vec2(a3 * c - w3 * s, a3 * s + w3 * c);
  }

  // The time derivatives of the free forces along a motion (the state's
  // velocities k and accelerations), under the prescribed drive d: the
  // free forces are linear in the state, so d F_r / dt = -k_r r_r' - b_r
  // r_r'' + rotor_free_force_rate(d), d F_s / dt = -k_s r_s' - b_s r_s''
  // [N/s] (the jerks of free flight and contact in closed form,
  // dense_high_order.hpp, constrained_dynamics.hpp).
  Vec2 rotor_free_force_derivative(const Kinematics& k, const Vec2& rotor_acc, const DriveState& d) const {
    return rotor_free_force_derivative(k, rotor_acc, d, unbalance_dir(d.angle_rad));
  }
  Vec2 rotor_free_force_derivative(const Kinematics& k, const Vec2& rotor_acc, const DriveState& d,
                                   const Vec2& unbalance_dir) const {
    return (-p_.rotor_stiffness_N_per_m * k.rotor_vel - p_.rotor_damping_N_s_per_m * rotor_acc) +
           rotor_free_force_rate(d, unbalance_dir);
  }
  FreeLoads free_loads(const Kinematics& k, const DriveState& d) const {
    return free_loads(k, d, unbalance_dir(d.angle_rad));
  }
  // The same, given the unbalance's direction (cos phi, sin phi) of d.angle_rad.
  FreeLoads free_loads(const Kinematics& k, const DriveState& d, const Vec2& unbalance_dir) const {
    FreeLoads f;
    f.unbalance_dir = unbalance_dir;
    f.rotor_N = motor_ ? shaft_force(k) : rotor_free_force(k, d, unbalance_dir);
    f.stator_N = stator_free_force(k);
    if (motor_) f.spin = spin_coupling(unbalance_dir, d.speed_rad_per_s);
    return f;
  }
  // The Jeffcott's SpinCoupling at the unbalance's direction and spin speed w.
  SpinCoupling spin_coupling(const Vec2& unbalance_dir, double w) const {
    const double c = unbalance_dir.x(), s = unbalance_dir.y(), e = p_.eccentricity_m;
    SpinCoupling sc;
    sc.lever_m = Vec2(e * s, -e * c);
    sc.inv_inertia_per_kg_m2 = inv_polar_inertia_;
    sc.bias_acc_m_per_s2 = Vec2(e * w * w * c, e * w * w * s - p_.gravity_m_per_s2);
    return sc;
  }

  // Accelerations of rotor, stator and spin under given contact forces, for
  // the drive d of drive_at() [m/s^2, rad/s^2].
  Accelerations accelerations(const Kinematics& k, const DriveState& d, const ContactGeometry& g, double normal_force_N,
                              double tangential_force_N) const {
    return accelerations(d, g, free_loads(k, d), normal_force_N, tangential_force_N);
  }
  // The compliance W of the contact (ContactCompliance) at g under drive d.
  // The Jeffcott's, whose spin coupling follows from d.
  ContactCompliance contact_compliance(const ContactGeometry& g, const DriveState& d) const {
    return contact_compliance(g,
                              motor_ ? spin_coupling(unbalance_dir(d.angle_rad), d.speed_rad_per_s) : SpinCoupling());
  }
  // The Jeffcott's, whose spin coupling follows from k.
  double apply_impulse(const ContactGeometry& g, double normal_impulse_N_s, double tangential_impulse_N_s,
                       Kinematics& k) const {
    const SpinCoupling sc =
        motor_ ? spin_coupling(unbalance_dir(k.spin.angle_rad), k.spin.speed_rad_per_s) : SpinCoupling();
    return apply_impulse(g, normal_impulse_N_s, tangential_impulse_N_s, sc, k);
  }

 private:
  double inv_polar_inertia_;
  Vec2 rotor_spring_centre_;
};

}  // namespace rotor_rub::core
