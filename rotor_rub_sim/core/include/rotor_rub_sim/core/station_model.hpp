// The rub station and the stator (model.hpp's modelling choices): what the
// contact sees of any rotor, a point of mass m_r at radius R_r pressed on
// by the stator, with the contact's geometry, its compliance and impulses,
// the drive, and the free loads a rotor model gives it (rotor_model.hpp).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"
#include "rotor_rub_sim/core/state_layout.hpp"

namespace rotor_rub::core {

// Accelerations of both bodies and of the spin [m/s^2, rad/s^2].
struct Accelerations {
  Vec2 rotor = Vec2::Zero();
  Vec2 stator = Vec2::Zero();
  double spin_rad_per_s2 = 0.0;
};

// How the spin and the rotor's translation drive each other under a motor
// drive (the unbalances' lever), in one form for the Jeffcott and a flexible
// rotor's station (flexible_rotor_model.hpp), F the rotor's forces at its
// centre (free and contact):
//   A   = (T_m + R_r F_t + extra_torque + lever . F) / J_eff,
//   a_r = F / m_r + A lever + bias_acc.
// The Jeffcott: lever = e u, J_eff = J_G, extra 0, bias e w^2 (cos, sin) - g y
// (the header comment). A flexible rotor: lever = h_u / m_st, J_eff = J -
// h^T M^-1 h, extra = h_xi . F_xi and, under gravity, the unbalances'
// pendulum torque, bias 0, with h the unbalances' lever on the reduced
// coordinates (FlexibleRotorModel::spin_coupling).
struct SpinCoupling {
  Vec2 lever_m = Vec2::Zero();
  double inv_inertia_per_kg_m2 = 0.0;  // 1 / J_eff
  double extra_torque_N_m = 0.0;
  Vec2 bias_acc_m_per_s2 = Vec2::Zero();
};

// How the relative velocity at the contact (normal v_n = delta', sliding
// v_slide) answers a contact force or impulse on the rotor, -F_n n + F_t t:
// d(v_n, v_slide) = W (-F_n, F_t) dt. W = I / m_eff + h h^T / J_G with
// h = (e n . u, R_r + e t . u) under a motor drive (the spin takes part),
// W = I / m_eff under the prescribed drive (the spin cannot).
struct ContactCompliance {
  double nn = 0.0, nt = 0.0, tt = 0.0;  // [1/kg]
};

struct ContactGeometry {
  double distance_m = 0.0;                // delta = |r_r - r_s|
  double penetration_m = 0.0;             // delta - C (> 0: rotor beyond the clearance)
  double normal_velocity_m_per_s = 0.0;   // delta' (> 0: closing into the stator)
  double sliding_velocity_m_per_s = 0.0;  // v_slide (see the header comment)
  Vec2 normal = Vec2::UnitX();            // n, outward from the stator's centre
  Vec2 tangent = Vec2::UnitY();           // t = n rotated +90 deg
};

// The loads of a state that do not depend on the contact forces, as a rotor
// model gives them (rotor_model.hpp): where several trial forces meet one
// state (the iteration method's roots, a sample) they are computed once,
// with the unbalance's sin/cos, not again for every trial force.
struct FreeLoads {
  Vec2 unbalance_dir = Vec2::UnitX();  // (cos phi, sin phi) of the spin angle
  Vec2 rotor_N = Vec2::Zero();         // on the station: every force but the contact's (a motor's A share apart)
  Vec2 stator_N = Vec2::Zero();        // StationModel::stator_free_force
  SpinCoupling spin;                   // motor only: the rotor's spin coupling
};

// The rub station and the stator: what the contact sees of any rotor (the
// rotor models of rotor_model.hpp add the rotor's own forces, FreeLoads).
// The station is a point of mass m_r (rotor_mass_kg: the Jeffcott's disk, a
// flexible rotor's station mass) at radius R_r (rotor_radius_m); the shaft's
// stiffness, damping and eccentricity are the Jeffcott's (JeffcottModel), not
// the station's. Masses, the stator, the contact's geometry, its compliance
// and impulses, the drive.
class StationModel {
 public:
  explicit StationModel(const ModelParameters& p)
      : p_(p),
        inv_rotor_mass_(1.0 / p.rotor_mass_kg),
        inv_stator_mass_(p.stator_model == StatorModel::kRigid ? 0.0 : 1.0 / p.stator_mass_kg),
        effective_mass_kg_(1.0 / (inv_rotor_mass_ + inv_stator_mass_)),
        inv_clearance_(1.0 / p.clearance_m),
        has_friction_(p.friction_coefficient > 0.0),
        motor_(p.drive_model == DriveModel::kMotor),
        stator_offset_(p.stator_offset_x_m, p.stator_offset_y_m) {
    // A rigid stator has no state: the methods work in its frame (its centre
    // at the origin); samples are shifted back by +offset (frame_shift()). An
    // elastic stator's springs pull it to the offset; the frame is the
    // casing's.
    const bool rigid = p.stator_model == StatorModel::kRigid;
    stator_spring_centre_ = rigid ? Vec2::Zero() : stator_offset_;
    frame_shift_ = rigid ? stator_offset_ : Vec2::Zero();
  }

  // Where the methods start (t = 0): at rest, the rotor centred in the casing,
  // the stator at its rest position; in the methods' frame.
  // A motor drive starts at the speed profile's initial angle and speed
  // (initial), with the controller's integrator empty.
  Kinematics initial_kinematics(const DriveState& initial = DriveState{}) const {
    Kinematics k;
    k.rotor_pos = Vec2::Zero() - frame_shift_;  // +0, not -0, without an offset
    k.stator_pos = stator_spring_centre_;
    if (motor_) {
      k.spin.angle_rad = initial.angle_rad;
      k.spin.speed_rad_per_s = initial.speed_rad_per_s;
    }
    return k;
  }
  // Methods' frame -> the casing's (what samples report): add this to positions.
  const Vec2& frame_shift() const { return frame_shift_; }

  const ModelParameters& parameters() const { return p_; }
  double inv_rotor_mass() const { return inv_rotor_mass_; }
  double inv_stator_mass() const { return inv_stator_mass_; }
  // m_r m_s / (m_r + m_s): the mass the contact sees (m_r for a rigid stator).
  double effective_mass_kg() const { return effective_mass_kg_; }
  double inv_clearance() const { return inv_clearance_; }  // 1 / C [1/m]
  bool has_friction() const { return has_friction_; }
  bool motor() const { return motor_; }
  // The unbalance's direction (cos, sin) of phi + beta: the mass centre lies
  // e along it from the geometric centre; beta (unbalance_phase_rad) is its
  // angle on the shaft from the keyphasor's notch (phi = 0).
  Vec2 unbalance_dir(double spin_angle_rad) const {
    const double a = spin_angle_rad + p_.unbalance_phase_rad;
    return Vec2(std::cos(a), std::sin(a));
  }

  // ---- The drive ----------------------------------------------------------

  // The drive as the forces see it at an instant, from the speed profile's
  // state there (reference): prescribed, the reference itself; motor, the
  // spin states with the motor's torque (accel_rad_per_s2 stays the
  // reference's until accelerations() gives the spin's own).
  DriveState drive_at(const Kinematics& k, const DriveState& reference) const {
    if (!motor_) return reference;
    DriveState d = reference;
    d.angle_rad = k.spin.angle_rad;
    d.speed_rad_per_s = k.spin.speed_rad_per_s;
    d.motor_torque_N_m = motor_output(k.spin, reference).torque_N_m;
    return d;
  }

  struct MotorOutput {
    double torque_N_m = 0.0;               // T_m, limited
    double integral_rate_rad_per_s = 0.0;  // z'
  };
  // The speed controller (header comment): PI with acceleration feed-forward,
  // torque limit and back-calculation anti-windup.
  MotorOutput motor_output(const SpinState& spin, const DriveState& reference) const {
    const double error = reference.speed_rad_per_s - spin.speed_rad_per_s;
    const double command = p_.rotor_polar_inertia_kg_m2 * reference.accel_rad_per_s2 +
                           p_.drive_proportional_gain_N_m_s_per_rad * error +
                           p_.drive_integral_gain_N_m_per_rad * spin.drive_integral_rad;
    MotorOutput out;
    out.torque_N_m = std::clamp(command, -p_.drive_torque_limit_N_m, p_.drive_torque_limit_N_m);
    out.integral_rate_rad_per_s = error + (out.torque_N_m - command) / p_.drive_proportional_gain_N_m_s_per_rad;
    return out;
  }

  // The drive's torque on the station's spin [N m]: the motor's, or the one
  // an ideal prescribed drive needs for the spin acceleration A it imposes
  // against the rub, J A - R_r F_t. A rotor's lateral motion acting on the
  // spin through its unbalances is the rotor model's to add (finish_sample:
  // the Jeffcott's - e F . u, a flexible rotor's - h^T q'').
  double station_drive_torque_N_m(const DriveState& d, double tangential_force_N) const {
    if (motor_) return d.motor_torque_N_m;
    return p_.rotor_polar_inertia_kg_m2 * d.accel_rad_per_s2 - p_.rotor_radius_m * tangential_force_N;
  }
  // The rub's torque on the rotor about its spin axis [N m] (< 0 brakes a
  // rotor spinning forward).
  double friction_torque_N_m(double tangential_force_N) const { return p_.rotor_radius_m * tangential_force_N; }

  Vec2 stator_free_force_derivative(const Kinematics& k, const Vec2& stator_acc) const {
    if (p_.stator_model == StatorModel::kRigid) return Vec2::Zero();
    return -p_.stator_stiffness_N_per_m * k.stator_vel - p_.stator_damping_N_s_per_m * stator_acc;
  }

  // All forces on the stator except contact [N] (zero for a rigid stator,
  // whose acceleration is zero anyway).
  Vec2 stator_free_force(const Kinematics& k) const {
    if (p_.stator_model == StatorModel::kRigid) return Vec2::Zero();
    // Per component, as rotor_free_force (the store forwarding).
    const double ks = -p_.stator_stiffness_N_per_m, bs = p_.stator_damping_N_s_per_m;
    const double fx = ks * (k.stator_pos.x() - stator_spring_centre_.x()) - bs * k.stator_vel.x();
    const double fy = (ks * (k.stator_pos.y() - stator_spring_centre_.y()) - bs * k.stator_vel.y()) -
                      p_.stator_mass_kg * p_.gravity_m_per_s2;
    return Vec2(fx, fy);
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

  // Moves both bodies along n so that delta = C and removes the normal
  // relative velocity, each in inverse proportion to its mass (momentum is
  // kept): the iteration method's projection onto the bore.
  void project_onto_bore(const ContactGeometry& g, Kinematics& k) const {
    const double im = inv_rotor_mass_ + inv_stator_mass_;
    k.rotor_pos -= g.penetration_m * (inv_rotor_mass_ / im) * g.normal;
    k.stator_pos += g.penetration_m * (inv_stator_mass_ / im) * g.normal;
    k.rotor_vel -= g.normal_velocity_m_per_s * (inv_rotor_mass_ / im) * g.normal;
    k.stator_vel += g.normal_velocity_m_per_s * (inv_stator_mass_ / im) * g.normal;
  }
  // Removes the sliding velocity the same way (v_slide = 0: rolling held).
  void hold_rolling(const ContactGeometry& g, Kinematics& k) const {
    const double im = inv_rotor_mass_ + inv_stator_mass_;
    k.rotor_vel -= g.sliding_velocity_m_per_s * (inv_rotor_mass_ / im) * g.tangent;
    k.stator_vel += g.sliding_velocity_m_per_s * (inv_stator_mass_ / im) * g.tangent;
  }

  // The contact force on the rotor for normal force F_n >= 0 and tangential
  // force F_t along t [N] (the stator gets the opposite).
  static Vec2 contact_force_on_rotor(const ContactGeometry& g, double normal_force_N, double tangential_force_N) {
    return -normal_force_N * g.normal + tangential_force_N * g.tangent;
  }

  // Accelerations of rotor, stator and spin under given contact forces, for
  // the drive d of drive_at() and the state's free loads (its rotor model's) [m/s^2, rad/s^2].
  Accelerations accelerations(const DriveState& d, const ContactGeometry& g, const FreeLoads& free,
                              double normal_force_N, double tangential_force_N) const {
    Accelerations a;
    const Vec2 on_rotor = contact_force_on_rotor(g, normal_force_N, tangential_force_N);
    if (!motor_) {
      a.rotor = (free.rotor_N + on_rotor) * inv_rotor_mass_;
      a.spin_rad_per_s2 = d.accel_rad_per_s2;
    } else {
      // The spin equation first (SpinCoupling), then the rotor's with it.
      const SpinCoupling& sc = free.spin;
      const Vec2 at_centre = free.rotor_N + on_rotor;
      a.spin_rad_per_s2 = (d.motor_torque_N_m + p_.rotor_radius_m * tangential_force_N + sc.extra_torque_N_m +
                           sc.lever_m.dot(at_centre)) *
                          sc.inv_inertia_per_kg_m2;
      a.rotor = at_centre * inv_rotor_mass_ + a.spin_rad_per_s2 * sc.lever_m + sc.bias_acc_m_per_s2;
    }
    a.stator = (free.stator_N - on_rotor) * inv_stator_mass_;
    return a;
  }

  // The compliance W of the contact (ContactCompliance) at g for the state's
  // spin coupling (a motor's; FreeLoads::spin):
  // with h = (n . lever, R_r + t . lever), W = I / m_eff + h h^T / J_eff.
  ContactCompliance contact_compliance(const ContactGeometry& g, const SpinCoupling& sc) const {
    ContactCompliance w;
    const double im = inv_rotor_mass_ + inv_stator_mass_;
    w.nn = w.tt = im;
    if (motor_) {
      const double hn = g.normal.dot(sc.lever_m);
      const double ht = p_.rotor_radius_m + g.tangent.dot(sc.lever_m);
      w.nn += hn * hn * sc.inv_inertia_per_kg_m2;
      w.nt = hn * ht * sc.inv_inertia_per_kg_m2;
      w.tt += ht * ht * sc.inv_inertia_per_kg_m2;
    }
    return w;
  }

  // Applies an impulse on the rotor P (-P_n n + P_t t at the contact; the
  // stator gets the opposite) to the velocities, the spin's included (the
  // state's spin coupling sc, a motor's). Returns the spin speed's jump
  // [rad/s] (0 under the prescribed drive): a flexible rotor's modes take
  // their share of it (FlexibleRotorModel::add_spin_share).
  double apply_impulse(const ContactGeometry& g, double normal_impulse_N_s, double tangential_impulse_N_s,
                       const SpinCoupling& sc, Kinematics& k) const {
    const Vec2 on_rotor = contact_force_on_rotor(g, normal_impulse_N_s, tangential_impulse_N_s);
    k.rotor_vel += on_rotor * inv_rotor_mass_;
    k.stator_vel -= on_rotor * inv_stator_mass_;
    if (!motor_) return 0.0;
    const double dw =
        (p_.rotor_radius_m * tangential_impulse_N_s + sc.lever_m.dot(on_rotor)) * sc.inv_inertia_per_kg_m2;
    k.spin.speed_rad_per_s += dw;
    k.rotor_vel += dw * sc.lever_m;
    return dw;
  }
  // Second time derivative of delta for given accelerations:
  // delta'' = n . (a_r - a_s) + |v_rel . t|^2 / delta.
  static double distance_acceleration(const Kinematics& k, const ContactGeometry& g, const Accelerations& a) {
    const double vt = (k.rotor_vel - k.stator_vel).dot(g.tangent);
    return g.normal.dot(a.rotor - a.stator) + vt * vt / g.distance_m;
  }

  // Time derivative of v_slide for given accelerations:
  // v_slide' = t . (a_r - a_s) - (v_rel . n)(v_rel . t) / delta + A R_r.
  double sliding_acceleration(const Kinematics& k, const ContactGeometry& g, const Accelerations& a) const {
    const Vec2 v = k.rotor_vel - k.stator_vel;
    return g.tangent.dot(a.rotor - a.stator) - v.dot(g.normal) * v.dot(g.tangent) / g.distance_m +
           a.spin_rad_per_s2 * p_.rotor_radius_m;
  }

 protected:
  ModelParameters p_;
  double inv_rotor_mass_;
  double inv_stator_mass_;
  double effective_mass_kg_;
  double inv_clearance_;
  bool has_friction_;
  bool motor_;
  Vec2 stator_offset_, stator_spring_centre_, frame_shift_;
};

// The drive's rows of a method's derivative (kMotor only): phi' = w,
// w' = the spin acceleration, z' = the controller's integral rate.
template <class L, class State>
void spin_derivative(const StationModel& m, const Kinematics& k, const DriveState& reference, double spin_acc,
                     State& dxdt) {
  if constexpr (L::kSpinSize > 0) {
    dxdt[L::kSpinAngle] = k.spin.speed_rad_per_s;
    dxdt[L::kSpinSpeed] = spin_acc;
    dxdt[L::kDriveIntegral] = m.motor_output(k.spin, reference).integral_rate_rad_per_s;
  }
}

// A FreeLayout state's derivative from its kinematics and accelerations a
// (the penalty and iteration methods): positions' rates the velocities, the
// velocities' the accelerations, the drive's rows (spin_derivative).
template <class L, class State>
void free_derivative(const StationModel& m, const Kinematics& k, const DriveState& reference, const Accelerations& a,
                     State& dxdt) {
  dxdt.template segment<2>(L::kRotorPos) = k.rotor_vel;
  dxdt.template segment<2>(L::kRotorVel) = a.rotor;
  if constexpr (L::kDof == 4) {  // the elastic stator's
    dxdt.template segment<2>(L::kStatorPos) = k.stator_vel;
    dxdt.template segment<2>(L::kStatorVel) = a.stator;
  }
  spin_derivative<L>(m, k, reference, a.spin_rad_per_s2, dxdt);
}

}  // namespace rotor_rub::core
