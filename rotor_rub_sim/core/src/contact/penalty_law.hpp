// The penalty method's contact law (contact_law.hpp) split into the smooth
// pieces an integrator can take, and the edges between them.
//
// The clamped law
//   F_n = max(0, k_c (delta - C) + c_c delta')  while delta > C, else 0,
//   F_t = -clamp(c_t v_slide, -f F_n, f F_n)
// is continuous in the state except at touchdown (F_n jumps to c_c delta'),
// and its derivative jumps where F_n returns to 0 and at the two edges of the
// friction cap. An integrator stepping across such a kink loses its order:
// its error estimate no longer shrinks with the step, so the controller
// rejects and shrinks until it stalls (Rosenbrock 4 at rtol 1e-8 on the paper
// scene, 6e-15 s at the first touchdown) and explicit methods waste
// rejections. The method therefore integrates one smooth piece (a mode) at a
// time, with its law extended smoothly past the edge, locates the edge on the
// dense output and restarts there, as the switching method does for its
// regimes. Inside a mode the force equals the clamped law's, so the solution
// is the clamped law's; only the numerics change.
//
// The mode is a function of the signs of three continuous edge functions [N]:
//   pressed = min(k_c p, k_c p + c_c p') > 0   (p = delta - C): F_n > 0
//   upper   = c_t v_slide - f F_n > 0           : slipping, F_t = -f F_n
//   lower   = -c_t v_slide - f F_n > 0          : slipping, F_t = +f F_n
// neither upper nor lower: the damper's linear range, F_t = -c_t v_slide
// (the law's stick, a creep at |F_t| / c_t). Without friction the tangential
// force is 0 and the friction edges are not watched. The force is continuous
// across the edges where F_n = 0 and at the cap, so an edge is crossed
// transversally unless touched with zero slope (a graze), where the method
// takes one step on the clamped law (penalty_method_impl.hpp).
//
// The penalty method's touchdown and lift-off events are the pressed edge's
// crossings: the force switching on and off. A force that returns while the
// rotor still penetrates (a rebound that turns back before the bore) is a
// touchdown whose normal velocity is negative (opening).
#pragma once

#include <algorithm>
#include <array>

#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/model.hpp"

namespace rotor_rub::core {

struct PenaltyMode {
  bool pressed = false;
  int slip = 0;          // +1: F_t = -f F_n; -1: F_t = +f F_n; 0: the linear range (or no friction)
  bool clamped = false;  // a fallback step on the clamped law itself (penalty_method_impl.hpp)
  bool operator==(const PenaltyMode& o) const { return pressed == o.pressed && slip == o.slip; }
  bool operator!=(const PenaltyMode& o) const { return !(*this == o); }
};

enum PenaltyEdge { kPressedEdge = 0, kUpperEdge = 1, kLowerEdge = 2, kPenaltyEdges = 3 };
using PenaltyEdgeValues = std::array<double, kPenaltyEdges>;  // [N]

struct PenaltyLaw {
  double stiffness_N_per_m = 0.0;
  double damping_N_s_per_m = 0.0;
  double friction_coefficient = 0.0;
  double tangential_damping_N_s_per_m = 0.0;

  PenaltyLaw() = default;
  explicit PenaltyLaw(const StationModel& m)
      : stiffness_N_per_m(m.parameters().contact_stiffness_N_per_m),
        damping_N_s_per_m(contact_damping_N_s_per_m(m)),
        friction_coefficient(m.parameters().friction_coefficient),
        tangential_damping_N_s_per_m(::rotor_rub::core::tangential_damping_N_s_per_m(m)) {}

  bool has_friction() const { return friction_coefficient > 0.0; }

  // The spring-dashpot force, unclamped: the pressed mode's smooth extension.
  double spring_dashpot_N(const ContactGeometry& g) const {
    return stiffness_N_per_m * g.penetration_m + damping_N_s_per_m * g.normal_velocity_m_per_s;
  }

  // The clamped law (what every sample reports).
  double normal(const ContactGeometry& g) const {
    if (g.penetration_m <= 0.0) return 0.0;
    return std::max(0.0, spring_dashpot_N(g));
  }
  double tangential(const ContactGeometry& g, double normal_N) const {
    return penalty_friction_N(friction_coefficient, normal_N, tangential_damping_N_s_per_m, g.sliding_velocity_m_per_s);
  }

  // The law of one mode, smooth in the state.
  double normal(const ContactGeometry& g, const PenaltyMode& mode) const {
    return mode.pressed ? spring_dashpot_N(g) : 0.0;
  }
  double tangential(const ContactGeometry& g, double normal_N, const PenaltyMode& mode) const {
    if (!mode.pressed || !has_friction()) return 0.0;
    if (mode.slip != 0) return -mode.slip * friction_coefficient * normal_N;
    return -tangential_damping_N_s_per_m * g.sliding_velocity_m_per_s;
  }

  PenaltyEdgeValues edges(const ContactGeometry& g) const {
    const double spring_N = stiffness_N_per_m * g.penetration_m;
    const double fn = spring_dashpot_N(g);
    const double damper_N = tangential_damping_N_s_per_m * g.sliding_velocity_m_per_s;
    const double cap_N = friction_coefficient * fn;
    return {std::min(spring_N, fn), damper_N - cap_N, -damper_N - cap_N};
  }

  PenaltyMode mode_of(const PenaltyEdgeValues& e) const {
    PenaltyMode m;
    m.pressed = e[kPressedEdge] > 0.0;
    if (m.pressed && has_friction()) m.slip = e[kUpperEdge] > 0.0 ? 1 : (e[kLowerEdge] > 0.0 ? -1 : 0);
    return m;
  }

  // The derivatives of one mode's contact force on the rotor,
  // F_c = -F_n n + F_t t, with rel = r_r - r_s, delta = |rel|, n = rel / delta,
  // t = (-n_y, n_x), v_n = rel' . n, v_t = rel' . t (station_model.hpp's geometry):
  //   dn/drel = t t^T / delta, dt/drel = -n t^T / delta,
  //   dF_n = k_c n^T drel + (c_c v_t / delta) t^T drel + c_c n^T drel',
  //   dv_slide = -(v_n / delta) t^T drel + t^T drel' + A R_r dt,
  //   F_t = -s f F_n (slip s) or -c_t v_slide (the linear range),
  //   dF_c = -n dF_n - F_n t t^T drel / delta + t dF_t - F_t n t^T drel / delta.
  // drive_slide_rate_m_per_s2 is A R_r: the sliding speed's rate through the
  // drive alone (the time's partial). Zero outside the pressed mode.
  struct ForceJacobian {
    Eigen::Matrix2d d_rel_pos = Eigen::Matrix2d::Zero();  // dF_c / drel [N/m]
    Eigen::Matrix2d d_rel_vel = Eigen::Matrix2d::Zero();  // dF_c / drel' [N s/m]
    Vec2 d_time = Vec2::Zero();                           // dF_c / dt at a fixed state [N/s]
  };
  ForceJacobian force_jacobian(const ContactGeometry& g, const Vec2& rel_vel, const PenaltyMode& mode,
                               double drive_slide_rate_m_per_s2) const {
    ForceJacobian j;
    if (!mode.pressed) return j;
    const Vec2& n = g.normal;
    const Vec2& t = g.tangent;
    const double inv_delta = 1.0 / g.distance_m;
    const double vn = g.normal_velocity_m_per_s, vt = rel_vel.dot(t);
    const double fn = spring_dashpot_N(g), ft = tangential(g, fn, mode);
    const Eigen::RowVector2d dfn_pos =
        stiffness_N_per_m * n.transpose() + damping_N_s_per_m * vt * inv_delta * t.transpose();
    const Eigen::RowVector2d dfn_vel = damping_N_s_per_m * n.transpose();
    Eigen::RowVector2d dft_pos = Eigen::RowVector2d::Zero(), dft_vel = Eigen::RowVector2d::Zero();
    double dft_time = 0.0;
    if (has_friction() && mode.slip != 0) {
      const double ratio = -mode.slip * friction_coefficient;
      dft_pos = ratio * dfn_pos;
      dft_vel = ratio * dfn_vel;
    } else if (has_friction()) {
      const double ct = tangential_damping_N_s_per_m;
      dft_pos = ct * vn * inv_delta * t.transpose();
      dft_vel = -ct * t.transpose();
      dft_time = -ct * drive_slide_rate_m_per_s2;
    }
    j.d_rel_pos =
        -n * dfn_pos + t * dft_pos - (fn * inv_delta) * (t * t.transpose()) - (ft * inv_delta) * (n * t.transpose());
    j.d_rel_vel = -n * dfn_vel + t * dft_vel;
    j.d_time = dft_time * t;
    return j;
  }

  // Whether a sign change of edge k can change the mode `from`.
  bool watched(int k, const PenaltyMode& from) const { return k == kPressedEdge || (from.pressed && has_friction()); }
};

}  // namespace rotor_rub::core
