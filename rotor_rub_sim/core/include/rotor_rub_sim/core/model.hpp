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

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <type_traits>

#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"

namespace rotor_rub::core {

using Vec2 = Eigen::Vector2d;

// The drive's states of a motor drive (unused with the prescribed drive).
struct SpinState {
  double angle_rad = 0.0;           // phi
  double speed_rad_per_s = 0.0;     // w = phi'
  double drive_integral_rad = 0.0;  // z: the speed controller's integrated speed error
};

// The drive's three states at the end of a method's state vector (kMotor
// only), after the positions and velocities: kBase is where they start.
template <bool kMotor, int kBase>
struct SpinLayout {
  static constexpr int kSpinSize = kMotor ? 3 : 0;
  static constexpr int kSpinAngle = kBase;          // phi [rad]
  static constexpr int kSpinSpeed = kBase + 1;      // w [rad/s]
  static constexpr int kDriveIntegral = kBase + 2;  // z [rad]
};

// A flexible rotor (flexible_rotor_model.hpp) carries its modal
// coordinates xi and their rates after a layout's fixed part: at most
// kMaxModalCoordinates of each (128 planar modes, the station's and 127 of
// the shaft's, in x/y pairs: the full FE model of a rotor of 64 nodes), in a
// state of dynamic size with that maximum (storage inside the vector, 4 kB:
// no allocation per step, test_allocations; matrices of the state's size
// are allocated once, dense_rodasp.hpp).
inline constexpr int kMaxPlanarModes = 128;
inline constexpr int kMaxModalCoordinates = 2 * (kMaxPlanarModes - 1);
/// [xi; xi'] of a flexible rotor [sqrt(kg) m, sqrt(kg) m/s] (empty: the Jeffcott).
using ModalState = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 2 * kMaxModalCoordinates, 1>;

// The state vector of a flexible rotor's layouts: every one is one type,
// with room for the largest fixed part (an elastic stator under a motor: 11,
// rounded up to 12 so that the 12 + 508 doubles are 16-byte aligned storage)
// and the modal block's maximum, so that a method's instances on one
// integrator (each stator, each drive, free flight and contact) share one set
// of Eigen and odeint instantiations, which shortens the flexible units'
// compile (docs/testing.md, "The longest compiles"). The free and contact
// states of a flexible rotor are thus one type: the layouts' indices, not the
// compiler, keep them apart.
inline constexpr int kMaxFixedStates = 12;
using FlexibleState = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxFixedStates + 2 * kMaxModalCoordinates, 1>;

// The rotor models (rotor_model.hpp): a layout's third parameter, whose
// State<kFixed> is the layout's state (fixed size without a modal block).
class JeffcottRotor;
class FlexibleRotor;

// Layout of the free (unconstrained) state vector. kStatorDof is 2 for an
// elastic stator and 0 for a rigid one; kMotor adds the drive's states;
// the rotor model its own block after them (kModal: a flexible rotor's xi,
// then xi', n each, n = modal_count()).
template <int kStatorDof, bool kMotor = false, class Rotor = JeffcottRotor>
struct FreeLayout : SpinLayout<kMotor, 2 * (2 + kStatorDof)> {
  static_assert(kStatorDof == 0 || kStatorDof == 2, "stator has 0 or 2 DOF");
  static constexpr int kDof = 2 + kStatorDof;
  static constexpr int kSize = 2 * kDof + SpinLayout<kMotor, 0>::kSpinSize;  // the fixed part
  static constexpr int kRotorPos = 0;          // x_r, y_r [m] (a flexible rotor's station)
  static constexpr int kStatorPos = 2;         // x_s, y_s [m] (elastic only)
  static constexpr int kRotorVel = kDof;       // x_r', y_r' [m/s]
  static constexpr int kStatorVel = kDof + 2;  // x_s', y_s' [m/s] (elastic only)
  static constexpr int kModal = kSize;         // the rotor's block: xi [sqrt(kg) m], then xi'
  using State = typename Rotor::template State<kSize>;
  static_assert(State::RowsAtCompileTime == Eigen::Dynamic || State::RowsAtCompileTime == kSize,
                "a fixed-size state is the layout's fixed part");
  static_assert(State::MaxRowsAtCompileTime >= kSize, "the state holds the layout's fixed part");
};

// A layout's state has a block when its size is dynamic.
template <class State>
inline constexpr bool kHasModalBlock = State::RowsAtCompileTime == Eigen::Dynamic;

// The modal coordinates in a state of layout L: how many (n), and the
// block [xi; xi'] (2 n entries from L::kModal).
template <class L, class State>
int modal_count(const State& x) {
  if constexpr (kHasModalBlock<State>) {
    return static_cast<int>(x.size() - L::kSize) / 2;
  } else {
    return 0;
  }
}
template <class L, class State>
ModalState modal_of(const State& x) {
  if constexpr (kHasModalBlock<State>) {
    return x.tail(x.size() - L::kSize);
  } else {
    return ModalState();
  }
}
// A state of layout L sized for a modal block (its fixed part unset).
template <class L>
typename L::State sized_state(const ModalState& modal) {
  typename L::State x;
  if constexpr (kHasModalBlock<typename L::State>) {
    x.resize(L::kSize + modal.size());
    x.tail(modal.size()) = modal;
  }
  return x;
}

// Positions and velocities of both bodies as plain 2-vectors (a rigid stator
// is at rest at the origin), and a motor drive's states.
struct Kinematics {
  Vec2 rotor_pos = Vec2::Zero();
  Vec2 rotor_vel = Vec2::Zero();
  Vec2 stator_pos = Vec2::Zero();
  Vec2 stator_vel = Vec2::Zero();
  SpinState spin;  // motor drive only
};

template <class L, class State>
void read_spin(const State& x, SpinState& spin) {
  if constexpr (L::kSpinSize > 0) {
    spin.angle_rad = x[L::kSpinAngle];
    spin.speed_rad_per_s = x[L::kSpinSpeed];
    spin.drive_integral_rad = x[L::kDriveIntegral];
  }
}

template <class L, class State>
void write_spin(const SpinState& spin, State& x) {
  if constexpr (L::kSpinSize > 0) {
    x[L::kSpinAngle] = spin.angle_rad;
    x[L::kSpinSpeed] = spin.speed_rad_per_s;
    x[L::kDriveIntegral] = spin.drive_integral_rad;
  }
}

// The modal block, if any, is not part of Kinematics (modal_of()).
template <int kStatorDof, bool kMotor = false, class Rotor = JeffcottRotor>
Kinematics kinematics_of(const typename FreeLayout<kStatorDof, kMotor, Rotor>::State& x) {
  using L = FreeLayout<kStatorDof, kMotor, Rotor>;
  Kinematics k;
  k.rotor_pos = x.template segment<2>(L::kRotorPos);
  k.rotor_vel = x.template segment<2>(L::kRotorVel);
  if constexpr (kStatorDof == 2) {
    k.stator_pos = x.template segment<2>(L::kStatorPos);
    k.stator_vel = x.template segment<2>(L::kStatorVel);
  }
  read_spin<L>(x, k.spin);
  return k;
}

// x sized already (sized_state() for a flexible rotor).
template <int kStatorDof, bool kMotor = false, class Rotor = JeffcottRotor>
void store_kinematics(const Kinematics& k, typename FreeLayout<kStatorDof, kMotor, Rotor>::State& x) {
  using L = FreeLayout<kStatorDof, kMotor, Rotor>;
  x.template segment<2>(L::kRotorPos) = k.rotor_pos;
  x.template segment<2>(L::kRotorVel) = k.rotor_vel;
  if constexpr (kStatorDof == 2) {
    x.template segment<2>(L::kStatorPos) = k.stator_pos;
    x.template segment<2>(L::kStatorVel) = k.stator_vel;
  }
  write_spin<L>(k.spin, x);
}

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

  // The torque the drive applies to the rotor [N m]: the motor's, or the one
  // an ideal prescribed drive needs for the spin acceleration A it imposes,
  // J_G A - R_r F_t - e F . u (the spin equation solved for T).
  double drive_torque_N_m(const Kinematics& k, const DriveState& d, const ContactGeometry& g, double normal_force_N,
                          double tangential_force_N) const {
    if (motor_) return d.motor_torque_N_m;
    return drive_torque_N_m(k, d, g, unbalance_dir(d.angle_rad), normal_force_N, tangential_force_N);
  }
  // The same, given the unbalance's direction (cos phi, sin phi) of d.angle_rad.
  double drive_torque_N_m(const Kinematics& k, const DriveState& d, const ContactGeometry& g, const Vec2& unbalance_dir,
                          double normal_force_N, double tangential_force_N) const {
    if (motor_) return d.motor_torque_N_m;
    const Vec2 u(unbalance_dir.y(), -unbalance_dir.x());
    const Vec2 at_centre = shaft_force(k) + contact_force_on_rotor(g, normal_force_N, tangential_force_N);
    return station_drive_torque_N_m(d, tangential_force_N) - p_.eccentricity_m * at_centre.dot(u);
  }
  // e F . u, the unbalance's lever torque on the spin that the prescribed
  // drive supplies besides J A - R_r F_t (station_drive_torque_N_m), for
  // kinematics in the casing's frame (a sample's: the shaft's spring centre
  // at the origin) and the contact force on the rotor [N m].
  double unbalance_torque_N_m(const Kinematics& casing, const DriveState& d, const Vec2& contact_force_N) const {
    const Vec2 dir = unbalance_dir(d.angle_rad);
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
