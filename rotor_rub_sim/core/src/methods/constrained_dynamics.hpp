// The rotor held on the stator's bore, |r_r - r_s| = C, in reduced
// coordinates: the stator's position (elastic stator) and the contact angle
// psi, with r_r = r_s + C n(psi), n = (cos psi, sin psi), t = n' = (-sin, cos);
// under a motor drive also the spin's states (state_layout.hpp).
//
// With r_r'' = r_s'' + C psi'' t - C psi'^2 n, the rotor's and stator's
// equations give the contact forces and psi'' in closed form
// (1/m = 1/m_r + 1/m_s, F_r and F_s the free forces (F_r the rotor model's), F_t the
// tangential force on the rotor along t):
//   F_n   = (F_r.n / m_r - F_s.n / m_s + C psi'^2) / (1/m)
//   slip:  F_t = -f F_n s,  psi'' = (F_r.t / m_r - F_s.t / m_s + F_t / m) / C
//   stick: v_slide = C psi' + w R_r = 0 held, so psi'' = -A R_r / C and
//          F_t = (C psi'' - F_r.t / m_r + F_s.t / m_s) / (1/m)
//   r_s'' = (F_s + F_n n - F_t t) / m_s.
// F_n does not depend on F_t (they act along n and t) under the prescribed
// drive. Under a motor drive the spin takes part: with the free relative
// accelerations a_n0 = n . (a_r - a_s), s0 = t . (a_r - a_s) + A R_r (no
// contact force) and the compliance W (station_model.hpp), the constraint
// n . (a_r - a_s) = -C psi'^2 and, in stick, v_slide' = 0 read
//   W_nn F_n - W_nt F_t = a_n0 + C psi'^2 =: b,   -W_nt F_n + W_tt F_t = -s0,
//   slip:  F_n = b / (W_nn + f s W_nt), F_t = -f s F_n;
//   stick: both equations, det = W_nn W_tt - W_nt^2 > 0.
// The rotor model (rotor_model.hpp) gives F_r, the station's free force, and
// the rows of its own block: a flexible rotor's station is a point of mass
// m_r = m_st, F_r takes the modal coordinates in, and their rows, xi'' from
// the same model, are the same in contact as in free flight (no contact
// force reaches them: the reduced mass is block-diagonal), but for a
// motor's spin, whose acceleration they share (A h_xi; the spin coupling's
// lever, inertia and torque then stand in the compliance W above).
#pragma once

#include <cmath>
#include <type_traits>

#include "contact/angle_pair.hpp"
#include "rotor/rotor_model.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/model.hpp"

namespace rotor_rub::core {

template <int kStatorDof, bool kMotor = false, class Rotor = JeffcottRotor>
struct ContactLayout : SpinLayout<kMotor, 2 * (1 + kStatorDof)> {
  static constexpr int kDof = 1 + kStatorDof;
  static constexpr int kSize = 2 * kDof + SpinLayout<kMotor, 0>::kSpinSize;  // the fixed part
  static constexpr int kStatorPos = 0;                                       // x_s, y_s [m] (elastic only)
  static constexpr int kAngle = kStatorDof;                                  // psi [rad]
  static constexpr int kStatorVel = kDof;                                    // x_s', y_s' [m/s] (elastic only)
  static constexpr int kAngleRate = kDof + kStatorDof;                       // psi' [rad/s]
  static constexpr int kModal = kSize;  // the rotor's block (state_layout.hpp's FreeLayout)
  using State = typename Rotor::template State<kSize>;
};

template <int kStatorDof, bool kMotor = false, class Rotor = JeffcottRotor>
struct ConstrainedDynamics {
  using L = ContactLayout<kStatorDof, kMotor, Rotor>;
  using State = typename L::State;
  const StationModel* model = nullptr;
  const Rotor* rotor = nullptr;
  FrictionMode mode;

  struct Result {
    Kinematics kin;
    DriveState drive;                   // the drive there (a motor's with its spin acceleration)
    double normal_force_N = 0.0;        // the constraint force; < 0 means lift-off
    double tangential_force_N = 0.0;    // F_t on the rotor along t
    double stick_force_N = 0.0;         // the F_t that would hold v_slide = 0
    double stick_normal_force_N = 0.0;  // F_n with it (= normal_force_N unless the spin takes part)
    double sliding_velocity_m_per_s = 0.0;
    double sliding_acc_m_per_s2 = 0.0;  // v_slide'
    double angle_acc_rad_per_s2 = 0.0;
    Vec2 stator_acc = Vec2::Zero();
    Vec2 unbalance_dir = Vec2::UnitX();  // (cos phi, sin phi) of the drive's angle (a sample's drive torque)
    Vec2 normal = Vec2::UnitX();         // n(psi) (prescribed drive: the jerk)
    Vec2 rotor_free_N = Vec2::Zero();    // F_r, F_s: the free forces (prescribed drive; the jerk)
    Vec2 stator_free_N = Vec2::Zero();
    typename Rotor::ModalVector modal_acc;  // the block's xi'' (a flexible rotor's)
  };

  Kinematics kinematics(const State& x) const {
    const double psi = x[L::kAngle];
    const Vec2 n(std::cos(psi), std::sin(psi)), t(-n.y(), n.x());
    return kinematics(x, n, t);
  }

  // The same, given n and t of the state's psi.
  Kinematics kinematics(const State& x, const Vec2& n, const Vec2& t) const {
    const double c = model->parameters().clearance_m;
    const double rate = x[L::kAngleRate];
    Kinematics k;
    if constexpr (kStatorDof == 2) {
      k.stator_pos = x.template segment<2>(L::kStatorPos);
      k.stator_vel = x.template segment<2>(L::kStatorVel);
    }
    k.rotor_pos = k.stator_pos + c * n;
    k.rotor_vel = k.stator_vel + c * rate * t;
    read_spin<L>(x, k.spin);
    return k;
  }

  // Reduced coordinates of a state at the bore (the rotor is placed on the
  // bore along its current direction; its normal relative velocity dropped,
  // which the plastic impact has already made zero); a flexible rotor's
  // modal block [xi; xi'] carried over.
  State reduce(const Kinematics& k, const ModalState& modal = ModalState()) const {
    State x = sized_state<L>(modal);
    const Vec2 rel = k.rotor_pos - k.stator_pos;
    const double psi = std::atan2(rel.y(), rel.x());
    const Vec2 t(-std::sin(psi), std::cos(psi));
    if constexpr (kStatorDof == 2) {
      x.template segment<2>(L::kStatorPos) = k.stator_pos;
      x.template segment<2>(L::kStatorVel) = k.stator_vel;
    }
    x[L::kAngle] = psi;
    x[L::kAngleRate] = (k.rotor_vel - k.stator_vel).dot(t) / model->parameters().clearance_m;
    write_spin<L>(k.spin, x);
    return x;
  }

  // The spin speed of the state x (the prescribed drive's from reference).
  double spin_speed(const State& x, const DriveState& reference) const {
    if constexpr (kMotor) {
      return x[L::kSpinSpeed];
    } else {
      return reference.speed_rad_per_s;
    }
  }

  // reference: the speed profile's state at the instant.
  Result evaluate(const State& x, const DriveState& reference) const {
    if constexpr (kMotor) {
      return evaluate_with_spin(x, reference);
    } else {
      const DriveState& d = reference;
      Result r;
      const double c = model->parameters().clearance_m;
      const double psi = x[L::kAngle], rate = x[L::kAngleRate];
      // On the bore by construction: the contact frame is psi's (no square
      // root or division to find it again from the positions). psi's and
      // the spin's unit vectors in one call (angle_pair.hpp).
      ContactGeometry g;
      Vec2 unbalance_dir;
      unit_vectors(psi, d.angle_rad + model->parameters().unbalance_phase_rad, g.normal, unbalance_dir);
      g.tangent = Vec2(-g.normal.y(), g.normal.x());
      g.distance_m = c;
      g.penetration_m = 0.0;
      g.normal_velocity_m_per_s = 0.0;
      g.sliding_velocity_m_per_s = c * rate + d.speed_rad_per_s * model->parameters().rotor_radius_m;
      r.kin = kinematics(x, g.normal, g.tangent);
      r.drive = d;
      r.unbalance_dir = unbalance_dir;
      r.normal = g.normal;
      const double imr = model->inv_rotor_mass(), ims = model->inv_stator_mass(), im = imr + ims;
      r.modal_acc.resize(modal_count<L>(x));
      const Vec2 fr = rotor->station_force(*model, r.kin, d, unbalance_dir, x.tail(x.size() - L::kSize), r.modal_acc);
      const Vec2 fs = model->stator_free_force(r.kin);
      const ModelParameters& p = model->parameters();
      // Products with the model's reciprocals m = 1 / (1/m_r + 1/m_s) and
      // 1 / C, not divisions: three divisions were a third of this
      // function's time (a switching run's hottest).
      const double effective_mass_kg = model->effective_mass_kg();
      r.normal_force_N = (fr.dot(g.normal) * imr - fs.dot(g.normal) * ims + c * rate * rate) * effective_mass_kg;
      r.stick_normal_force_N = r.normal_force_N;
      // Tangential relative acceleration without contact force, plus A R_r:
      // v_slide' = free_t + F_t / m.
      const double free_t = fr.dot(g.tangent) * imr - fs.dot(g.tangent) * ims + d.accel_rad_per_s2 * p.rotor_radius_m;
      r.stick_force_N = -free_t * effective_mass_kg;
      r.sliding_velocity_m_per_s = c * rate + d.speed_rad_per_s * p.rotor_radius_m;
      if (mode.stick) {
        r.tangential_force_N = r.stick_force_N;
      } else if (model->has_friction()) {
        r.tangential_force_N = -p.friction_coefficient * r.normal_force_N * mode.slip_sign;
      }
      r.sliding_acc_m_per_s2 = free_t + r.tangential_force_N * im;
      r.angle_acc_rad_per_s2 =
          (r.sliding_acc_m_per_s2 - d.accel_rad_per_s2 * p.rotor_radius_m) * model->inv_clearance();
      r.stator_acc = (fs + r.normal_force_N * g.normal - r.tangential_force_N * g.tangent) * ims;
      r.rotor_free_N = fr;
      r.stator_free_N = fs;
      return r;
    }
  }

  // The rates of the contact forces along the motion under the prescribed
  // drive (A constant on a speed segment), from the time derivatives of the
  // quantities above: n' = psi' t, t' = -psi' n, r_r'' = r_s'' + C psi'' t -
  // C psi'^2 n, F_r' the rotor model's station_force_rate, F_s' the stator's, and
  //   F_n'    = m ((F_r'.n + psi' F_r.t) / m_r - (F_s'.n + psi' F_s.t) / m_s + 2 C psi' psi'')
  //   free_t' = (F_r'.t - psi' F_r.n) / m_r - (F_s'.t - psi' F_s.n) / m_s
  //   F_t'    = -f s F_n' (slip), -m free_t' (stick: the stick force's rate), 0 (no friction).
  // The jerk below and the switching method's event rates share them (its
  // scan finds a lift-off or a breakaway between two scan points by them).
  // A flexible rotor's xi''' is written to modal_jerk.
  struct ForceRates {
    Vec2 stator_free_N_per_s = Vec2::Zero();  // F_s'
    double normal_N_per_s = 0.0;              // F_n'
    double free_tangential_m_per_s3 = 0.0;    // free_t'
    double stick_N_per_s = 0.0;               // F_t,stick' = -m free_t'
    double tangential_N_per_s = 0.0;          // F_t' in the current friction mode
  };
  template <class ModalJerk>
  ForceRates force_rates(const State& x, const Result& r, const DriveState& reference,
                         const Eigen::MatrixBase<ModalJerk>& modal_jerk) const {
    static_assert(!kMotor, "the motor's spin couples: differenced instead");
    const ModelParameters& p = model->parameters();
    const double c = p.clearance_m, rate = x[L::kAngleRate], acc = r.angle_acc_rad_per_s2;
    const double imr = model->inv_rotor_mass(), ims = model->inv_stator_mass();
    const Vec2& n = r.normal;
    const Vec2 t(-n.y(), n.x());
    const Vec2 rotor_acc = r.stator_acc + c * acc * t - c * rate * rate * n;
    const int m = modal_count<L>(x);
    ModalState rates(2 * m);  // fixed capacity: no allocation
    rates.head(m) = x.tail(m);
    rates.tail(m) = r.modal_acc;
    const Vec2 fr_rate =
        rotor->station_force_rate(*model, r.kin, rotor_acc, reference, r.unbalance_dir, rates, modal_jerk);
    ForceRates q;
    q.stator_free_N_per_s = model->stator_free_force_derivative(r.kin, r.stator_acc);
    const Vec2 &fr = r.rotor_free_N, &fs = r.stator_free_N, &fs_rate = q.stator_free_N_per_s;
    q.normal_N_per_s =
        ((fr_rate.dot(n) + rate * fr.dot(t)) * imr - (fs_rate.dot(n) + rate * fs.dot(t)) * ims + 2.0 * c * rate * acc) *
        model->effective_mass_kg();
    q.free_tangential_m_per_s3 = (fr_rate.dot(t) - rate * fr.dot(n)) * imr - (fs_rate.dot(t) - rate * fs.dot(n)) * ims;
    q.stick_N_per_s = -q.free_tangential_m_per_s3 * model->effective_mass_kg();
    if (mode.stick) {
      q.tangential_N_per_s = q.stick_N_per_s;
    } else if (model->has_friction()) {
      q.tangential_N_per_s = -p.friction_coefficient * mode.slip_sign * q.normal_N_per_s;
    }
    return q;
  }

  // The state's second derivative in closed form under the prescribed drive
  // (the jerk of the Hermite dense output, dense_high_order.hpp), from the
  // force rates above:
  //   psi'''  = (free_t' + F_t' / m) / C
  //   r_s'''  = (F_s' + F_n' n + F_n psi' t - F_t' t + F_t psi' n) / m_s.
  void second_derivative(const State& x, const DriveState& reference, State& ddx) const {
    second_derivative(x, evaluate(x, reference), reference, ddx);
  }
  // The same from the state's evaluation r = evaluate(x, reference).
  void second_derivative(const State& x, const Result& r, const DriveState& reference, State& ddx) const {
    const int m = modal_count<L>(x);
    ddx.resize(x.size());
    ddx.segment(L::kModal, m) = r.modal_acc;
    const ForceRates q = force_rates(x, r, reference, ddx.tail(m));
    const double rate = x[L::kAngleRate];
    const double ims = model->inv_stator_mass(), im = model->inv_rotor_mass() + ims;
    const Vec2& n = r.normal;
    const Vec2 t(-n.y(), n.x());
    ddx[L::kAngle] = r.angle_acc_rad_per_s2;
    ddx[L::kAngleRate] = (q.free_tangential_m_per_s3 + q.tangential_N_per_s * im) * model->inv_clearance();
    if constexpr (kStatorDof == 2) {
      ddx.template segment<2>(L::kStatorPos) = r.stator_acc;
      ddx.template segment<2>(L::kStatorVel) =
          (q.stator_free_N_per_s + q.normal_N_per_s * n + r.normal_force_N * rate * t - q.tangential_N_per_s * t +
           r.tangential_force_N * rate * n) *
          ims;
    }
  }

  void derivative(const State& x, const DriveState& reference, State& dxdt) const {
    derivative(x, evaluate(x, reference), reference, dxdt);
  }
  // The same from the state's evaluation r = evaluate(x, reference).
  void derivative(const State& x, const Result& r, const DriveState& reference, State& dxdt) const {
    const int m = modal_count<L>(x);
    dxdt.resize(x.size());
    dxdt.segment(L::kModal, m) = x.tail(m);
    dxdt.tail(m) = r.modal_acc;
    dxdt[L::kAngle] = x[L::kAngleRate];
    dxdt[L::kAngleRate] = r.angle_acc_rad_per_s2;
    if constexpr (kStatorDof == 2) {
      dxdt.template segment<2>(L::kStatorPos) = x.template segment<2>(L::kStatorVel);
      dxdt.template segment<2>(L::kStatorVel) = r.stator_acc;
    }
    spin_derivative<L>(*model, r.kin, reference, r.drive.accel_rad_per_s2, dxdt);
  }

 private:
  Result evaluate_with_spin(const State& x, const DriveState& reference) const {
    Result r;
    r.kin = kinematics(x);
    const ModelParameters& p = model->parameters();
    const double c = p.clearance_m;
    const double rate = x[L::kAngleRate];
    DriveState d = model->drive_at(r.kin, reference);
    const ContactGeometry g = model->contact_geometry(r.kin, d);
    // The free loads once for both accelerations below (model.hpp); a
    // flexible rotor's with the spin coupling of its unbalances.
    const int n = modal_count<L>(x);
    r.modal_acc.resize(n);
    const FreeLoads loads = rotor->loads(*model, r.kin, d, x.tail(2 * n), r.modal_acc);
    r.unbalance_dir = loads.unbalance_dir;
    const Accelerations free = model->accelerations(d, g, loads, 0.0, 0.0);
    const ContactCompliance w = model->contact_compliance(g, loads.spin);
    const double b = g.normal.dot(free.rotor - free.stator) + c * rate * rate;
    const double s0 = g.tangent.dot(free.rotor - free.stator) + free.spin_rad_per_s2 * p.rotor_radius_m;
    const double det = w.nn * w.tt - w.nt * w.nt;
    r.stick_normal_force_N = (b * w.tt - w.nt * s0) / det;
    r.stick_force_N = (w.nt * b - w.nn * s0) / det;
    if (mode.stick) {
      r.normal_force_N = r.stick_normal_force_N;
      r.tangential_force_N = r.stick_force_N;
    } else {
      const double f = model->has_friction() ? p.friction_coefficient : 0.0;
      // > 0 by validate_scene (Painleve's bound, contact_law.hpp).
      r.normal_force_N = b / (w.nn + f * mode.slip_sign * w.nt);
      r.tangential_force_N = -f * mode.slip_sign * r.normal_force_N;
    }
    const Accelerations a = model->accelerations(d, g, loads, r.normal_force_N, r.tangential_force_N);
    rotor->add_spin_share(loads.unbalance_dir, a.spin_rad_per_s2, r.modal_acc);
    d.accel_rad_per_s2 = a.spin_rad_per_s2;
    r.drive = d;
    r.sliding_velocity_m_per_s = g.sliding_velocity_m_per_s;
    const double rel_t = g.tangent.dot(a.rotor - a.stator);
    r.sliding_acc_m_per_s2 = rel_t + a.spin_rad_per_s2 * p.rotor_radius_m;
    r.angle_acc_rad_per_s2 = rel_t / c;
    r.stator_acc = a.stator;
    return r;
  }
};

}  // namespace rotor_rub::core
