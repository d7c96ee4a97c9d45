// The rotor held on the stator's bore, |r_r - r_s| = C, in reduced
// coordinates: the stator's position (elastic stator) and the contact angle
// psi, with r_r = r_s + C n(psi), n = (cos psi, sin psi), t = n' = (-sin, cos).
//
// With r_r'' = r_s'' + C psi'' t - C psi'^2 n, the rotor's and stator's
// equations give the contact forces and psi'' in closed form
// (1/m = 1/m_r + 1/m_s, F_r and F_s the free forces of model.hpp, F_t the
// tangential force on the rotor along t):
//   F_n   = (F_r.n / m_r - F_s.n / m_s + C psi'^2) / (1/m)
//   slip:  F_t = -f F_n s,  psi'' = (F_r.t / m_r - F_s.t / m_s + F_t / m) / C
//   stick: v_slide = C psi' + w R_r = 0 held, so psi'' = -A R_r / C and
//          F_t = (C psi'' - F_r.t / m_r + F_s.t / m_s) / (1/m)
//   r_s'' = (F_s + F_n n - F_t t) / m_s.
// F_n does not depend on F_t (they act along n and t).
#pragma once

#include <cmath>

#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/model.hpp"

namespace rotor_rub::core {

template <int kStatorDof>
struct ContactLayout {
  static constexpr int kDof = 1 + kStatorDof;
  static constexpr int kSize = 2 * kDof;
  static constexpr int kStatorPos = 0;                  // x_s, y_s [m] (elastic only)
  static constexpr int kAngle = kStatorDof;             // psi [rad]
  static constexpr int kStatorVel = kDof;               // x_s', y_s' [m/s] (elastic only)
  static constexpr int kAngleRate = kDof + kStatorDof;  // psi' [rad/s]
  using State = Eigen::Matrix<double, kSize, 1>;
};

template <int kStatorDof>
struct ConstrainedDynamics {
  using L = ContactLayout<kStatorDof>;
  using State = typename L::State;
  const JeffcottModel* model = nullptr;
  FrictionMode mode;

  struct Result {
    Kinematics kin;
    double normal_force_N = 0.0;      // the constraint force; < 0 means lift-off
    double tangential_force_N = 0.0;  // F_t on the rotor along t
    double stick_force_N = 0.0;       // the F_t that would hold v_slide = 0
    double sliding_velocity_m_per_s = 0.0;
    double sliding_acc_m_per_s2 = 0.0;  // v_slide'
    double angle_acc_rad_per_s2 = 0.0;
    Vec2 stator_acc = Vec2::Zero();
  };

  Kinematics kinematics(const State& x) const {
    const double c = model->parameters().clearance_m;
    const double psi = x[L::kAngle], rate = x[L::kAngleRate];
    const Vec2 n(std::cos(psi), std::sin(psi)), t(-n.y(), n.x());
    Kinematics k;
    if constexpr (kStatorDof == 2) {
      k.stator_pos = x.template segment<2>(L::kStatorPos);
      k.stator_vel = x.template segment<2>(L::kStatorVel);
    }
    k.rotor_pos = k.stator_pos + c * n;
    k.rotor_vel = k.stator_vel + c * rate * t;
    return k;
  }

  // Reduced coordinates of a state at the bore (the rotor is placed on the
  // bore along its current direction; its normal relative velocity dropped,
  // which the plastic impact has already made zero).
  State reduce(const Kinematics& k) const {
    State x;
    const Vec2 rel = k.rotor_pos - k.stator_pos;
    const double psi = std::atan2(rel.y(), rel.x());
    const Vec2 t(-std::sin(psi), std::cos(psi));
    if constexpr (kStatorDof == 2) {
      x.template segment<2>(L::kStatorPos) = k.stator_pos;
      x.template segment<2>(L::kStatorVel) = k.stator_vel;
    }
    x[L::kAngle] = psi;
    x[L::kAngleRate] = (k.rotor_vel - k.stator_vel).dot(t) / model->parameters().clearance_m;
    return x;
  }

  Result evaluate(const State& x, const DriveState& d) const {
    Result r;
    r.kin = kinematics(x);
    const double c = model->parameters().clearance_m;
    const double rate = x[L::kAngleRate];
    const ContactGeometry g = model->contact_geometry(r.kin, d);
    const double imr = model->inv_rotor_mass(), ims = model->inv_stator_mass(), im = imr + ims;
    const Vec2 fr = model->rotor_free_force(r.kin, d);
    const Vec2 fs = model->stator_free_force(r.kin);
    const ModelParameters& p = model->parameters();
    r.normal_force_N = (fr.dot(g.normal) * imr - fs.dot(g.normal) * ims + c * rate * rate) / im;
    // Tangential relative acceleration without contact force, plus A R_r:
    // v_slide' = free_t + F_t / m.
    const double free_t = fr.dot(g.tangent) * imr - fs.dot(g.tangent) * ims + d.accel_rad_per_s2 * p.rotor_radius_m;
    r.stick_force_N = -free_t / im;
    r.sliding_velocity_m_per_s = c * rate + d.speed_rad_per_s * p.rotor_radius_m;
    if (mode.stick) {
      r.tangential_force_N = r.stick_force_N;
    } else if (model->has_friction()) {
      r.tangential_force_N = -p.friction_coefficient * r.normal_force_N * mode.slip_sign;
    }
    r.sliding_acc_m_per_s2 = free_t + r.tangential_force_N * im;
    r.angle_acc_rad_per_s2 = (r.sliding_acc_m_per_s2 - d.accel_rad_per_s2 * p.rotor_radius_m) / c;
    r.stator_acc = (fs + r.normal_force_N * g.normal - r.tangential_force_N * g.tangent) * ims;
    return r;
  }

  void derivative(const State& x, const DriveState& d, State& dxdt) const {
    const Result r = evaluate(x, d);
    dxdt[L::kAngle] = x[L::kAngleRate];
    dxdt[L::kAngleRate] = r.angle_acc_rad_per_s2;
    if constexpr (kStatorDof == 2) {
      dxdt.template segment<2>(L::kStatorPos) = x.template segment<2>(L::kStatorVel);
      dxdt.template segment<2>(L::kStatorVel) = r.stator_acc;
    }
  }
};

}  // namespace rotor_rub::core
