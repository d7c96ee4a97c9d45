// The closed-form Jacobians the stiff integrator uses instead of differences,
// against central differences of the same right-hand side: the penalty
// method's (penalty_system.hpp) in every mode of the law (free, pressed in
// the linear range, slipping either way, the clamped law's fallback; the
// pressed mode also in its polar coordinates), and the switching and
// iteration methods' free flight (switching_systems.hpp,
// iteration_system.hpp); elastic and rigid stators, gravity, friction 0 to
// 1, restitution 0 and 0.7, below and far above the critical speed, the
// Jeffcott and flexible rotors, at random states (fixed seed).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "methods/iteration_system.hpp"
#include "methods/penalty_system.hpp"
#include "methods/switching_systems.hpp"
#include "rotor/rotor_model.hpp"
#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "test_support.hpp"

namespace rotor_rub {
namespace {

using core::PenaltyMode;

// Central differences: truncation (h / delta)^2 ~ 3e-13 relative for a
// position step of 1e-9 m on a 2e-3 m clearance, (w h_t)^2 / 6 ~ 2e-7 for
// the time step at 1500 rad/s; rounding 4 eps max|f| / h, added per column.
// The smallest term the test must see, the friction force's turning
// (F_t n t^T / delta), is 5e-4 of its block at f 0.1: kRelTolerance is far
// below it and far above the differences' truncation.
constexpr double kRelTolerance = 1e-6;
constexpr double kPositionStep_m = 1e-9;
constexpr double kVelocityStep_m_per_s = 1e-6;
constexpr double kTimeStep_s = 1e-6;

struct Case {
  std::string name;
  core::ModelParameters model;
  core::SpeedSegment segment;
};

std::vector<Case> cases() {
  const core::ModelParameters paper = test::paper_scene().model;
  const core::SpeedSegment run_up{0.5, 3.0, 150.0, 70.0};
  std::vector<Case> out;
  out.push_back({"paper", paper, run_up});
  Case c{"rigid stator, gravity, f 1.0", paper, {0.0, 1.0, 1500.0, 0.0}};
  c.model.stator_model = core::StatorModel::kRigid;
  c.model.gravity_m_per_s2 = 9.81;
  c.model.friction_coefficient = 1.0;
  out.push_back(c);
  c = {"elastic, no friction, restitution 0.7, far above critical", paper, {0.2, 10.0, 600.0, -40.0}};
  c.model.friction_coefficient = 0.0;
  c.model.restitution = 0.7;
  out.push_back(c);
  c = {"elastic, gravity, f 0.6, offset, k_c 1e11", paper, run_up};
  c.model.gravity_m_per_s2 = 9.81;
  c.model.friction_coefficient = 0.6;
  c.model.stator_offset_y_m = -1e-3;
  c.model.contact_stiffness_N_per_m = 1e11;
  out.push_back(c);
  return out;
}

template <class System>
typename System::State rhs(const System& sys, const typename System::State& x, double t) {
  typename System::State f;
  sys(x, f, t);
  return f;
}

// Compares the closed form with central differences at x (steps: each
// column's); returns the largest error over the tolerance (<= 1 passes).
// The differences' rounding floor: 4 eps of the largest derivative over the
// step; in row term_row of term_scale, the largest term that row sums, where
// that is larger.
template <class System>
double worst_ratio(const System& sys, const typename System::State& x, const typename System::State& steps, double t,
                   std::string* where, double term_scale = 0.0, int term_row = -1) {
  using State = typename System::State;
  typename System::Matrix jac;
  State dfdt;
  sys.jacobian(x, t, jac, dfdt);
  double worst = 0.0;
  const double fmax = rhs(sys, x, t).cwiseAbs().maxCoeff();
  auto check = [&](const State& fd, const State& exact, double h, const std::string& column) {
    for (int i = 0; i < x.size(); ++i) {
      const double scale = i == term_row ? std::max(fmax, term_scale) : fmax;
      const double rounding = 4.0 * std::numeric_limits<double>::epsilon() * scale / h;
      const double allowed = kRelTolerance * std::max(std::abs(fd[i]), std::abs(exact[i])) + rounding;
      const double ratio = std::abs(fd[i] - exact[i]) / allowed;
      if (ratio > worst) {
        worst = ratio;
        *where = "row " + std::to_string(i) + ", " + column + ": closed form " + std::to_string(exact[i]) +
                 ", differences " + std::to_string(fd[i]);
      }
    }
  };
  for (int j = 0; j < x.size(); ++j) {
    State xp = x, xm = x;
    xp[j] += steps[j];
    xm[j] -= steps[j];
    check((rhs(sys, xp, t) - rhs(sys, xm, t)) / (2.0 * steps[j]), jac.col(j), steps[j], "column " + std::to_string(j));
  }
  check((rhs(sys, x, t + kTimeStep_s) - rhs(sys, x, t - kTimeStep_s)) / (2.0 * kTimeStep_s), dfdt, kTimeStep_s, "d/dt");
  return worst;
}

template <int kStatorDof>
struct Checker {
  using System = core::PenaltySystem<kStatorDof, false, true>;
  using L = typename System::L;
  using State = typename System::State;
  using Matrix = typename System::Matrix;

  // A state whose rotor penetrates by 0 to 2e-5 m (or stands 1e-4 m off) at
  // a random angle, with random velocities of up to 1 m/s.
  static State random_state(std::mt19937& rng, const core::ModelParameters& p, bool penetrating) {
    std::uniform_real_distribution<double> unit(-1.0, 1.0), share(0.0, 1.0);
    State x = State::Zero();
    const double angle = M_PI * unit(rng);
    const double distance = p.clearance_m + (penetrating ? 2e-5 * share(rng) + 1e-9 : -1e-4);
    const core::Vec2 stator(1e-4 * unit(rng), 1e-4 * unit(rng));
    const core::Vec2 rel = distance * core::Vec2(std::cos(angle), std::sin(angle));
    x.template segment<2>(L::kRotorPos) = (kStatorDof == 2 ? stator : core::Vec2::Zero()) + rel;
    x.template segment<2>(L::kRotorVel) = core::Vec2(unit(rng), unit(rng));
    if constexpr (kStatorDof == 2) {
      x.template segment<2>(L::kStatorPos) = stator;
      x.template segment<2>(L::kStatorVel) = core::Vec2(0.3 * unit(rng), 0.3 * unit(rng));
    }
    return x;
  }

  static State steps() {
    State h;
    h.template head<L::kDof>().setConstant(kPositionStep_m);
    h.template tail<L::kDof>().setConstant(kVelocityStep_m_per_s);
    return h;
  }

  // Every mode's smooth law at random states, and the clamped law where the
  // differences stay inside one of its pieces.
  static void run(const Case& c) {
    const core::JeffcottModel model(c.model);
    const core::JeffcottRotor rotor(c.model);
    System sys;
    sys.model = &model;
    sys.rotor = &rotor;
    sys.law = core::PenaltyLaw(model);
    sys.segment = c.segment;
    std::mt19937 rng(20261125);
    const double t = c.segment.start_time_s + 0.37;
    std::vector<PenaltyMode> modes(4);
    modes[1].pressed = modes[2].pressed = modes[3].pressed = true;
    modes[2].slip = 1;
    modes[3].slip = -1;
    int clamped_checked = 0;
    for (int trial = 0; trial < 40; ++trial) {
      const State x = random_state(rng, c.model, trial % 8 != 0);
      for (const PenaltyMode& m : modes) {
        if (m.slip != 0 && !sys.law.has_friction()) continue;
        sys.mode = m;
        std::string where;
        EXPECT_LE(worst_ratio(sys, x, steps(), t, &where), 1.0)
            << c.name << ", trial " << trial << ", mode pressed " << m.pressed << " slip " << m.slip << ": " << where;
      }
      // The switching method's free flight at the same state (it knows no
      // contact: the penalty law's free mode without the law).
      core::FreeFlightSystem<kStatorDof, false, core::JeffcottRotor> free;
      free.model = &model;
      free.rotor = &rotor;
      free.segment = c.segment;
      std::string where_free;
      EXPECT_LE(worst_ratio(free, x, steps(), t, &where_free), 1.0)
          << c.name << ", trial " << trial << ", free flight: " << where_free;
      // The iteration method's system out of contact (its free flight on
      // rosenbrock4): the same free flight, in its own system.
      core::IterationSystem<kStatorDof, false, core::JeffcottRotor> iteration;
      iteration.model = &model;
      iteration.rotor = &rotor;
      iteration.segment = c.segment;
      EXPECT_LE(worst_ratio(iteration, x, steps(), t, &where_free), 1.0)
          << c.name << ", trial " << trial << ", the iteration method's free flight: " << where_free;
      // The clamped law: only where no difference step crosses an edge.
      sys.mode = PenaltyMode{};
      sys.mode.clamped = true;
      const auto mode_at = [&](const State& y) {
        const core::Kinematics ky = core::kinematics_of<kStatorDof, false>(y);
        return sys.law.mode_of(sys.law.edges(model.contact_geometry(ky, c.segment.at(t))));
      };
      const PenaltyMode here = mode_at(x);
      bool inside = true;
      for (int j = 0; j < L::kSize && inside; ++j) {
        const double h = j < L::kDof ? kPositionStep_m : kVelocityStep_m_per_s;
        State xp = x, xm = x;
        xp[j] += h;
        xm[j] -= h;
        inside = mode_at(xp) == here && mode_at(xm) == here;
      }
      if (!inside) continue;
      ++clamped_checked;
      std::string where;
      EXPECT_LE(worst_ratio(sys, x, steps(), t, &where), 1.0)
          << c.name << ", trial " << trial << ", clamped: " << where;
    }
    EXPECT_GE(clamped_checked, 30) << c.name << ": too few clamped-law states away from an edge";
  }
};

// The pressed mode in polar coordinates (PenaltyPolarSystem): its closed
// form, the chain rule through the Cartesian one, against differences.
template <int kStatorDof>
struct PolarChecker {
  using Cartesian = core::PenaltySystem<kStatorDof, false, true>;
  using System = core::PenaltyPolarSystem<kStatorDof, false>;
  using L = typename System::L;
  using State = typename System::State;

  // Steps: delta 1e-9 m and delta' 1e-6 m/s as the Cartesian ones; psi
  // 1e-4 rad (truncation (h / 1 rad)^2 / 6 ~ 2e-9); psi' 1e-2 rad/s (it
  // enters as psi' and psi'^2, which central differences take exactly);
  // the stator's 1e-6 m and 1e-4 m/s (they move both bodies: linear).
  static State steps() {
    State h;
    h.template head<L::kDof>().setConstant(1e-6);
    h.template tail<L::kDof>().setConstant(1e-4);
    h[L::kDistance] = kPositionStep_m;
    h[L::kDistanceRate] = kVelocityStep_m_per_s;
    h[L::kAngle] = 1e-4;
    h[L::kAngleRate] = 1e-2;
    return h;
  }

  // Pressed by 0 to 2e-5 m, at any angle (a whirl's grown angle, up to
  // 600 rad), closing or opening at up to 1e-3 m/s, whirling at up to
  // 300 rad/s either way.
  static State random_state(std::mt19937& rng, const core::ModelParameters& p) {
    std::uniform_real_distribution<double> unit(-1.0, 1.0), share(0.0, 1.0);
    State x = State::Zero();
    x[L::kDistance] = p.clearance_m + 2e-5 * share(rng) + 1e-9;
    x[L::kAngle] = 600.0 * unit(rng);
    x[L::kDistanceRate] = 1e-3 * unit(rng);
    x[L::kAngleRate] = 300.0 * unit(rng);
    if constexpr (kStatorDof == 2) {
      x.template segment<2>(L::kStatorPos) = core::Vec2(1e-4 * unit(rng), 1e-4 * unit(rng));
      x.template segment<2>(L::kStatorVel) = core::Vec2(0.3 * unit(rng), 0.3 * unit(rng));
    }
    return x;
  }

  static void run(const Case& c) {
    const core::JeffcottModel model(c.model);
    const core::JeffcottRotor rotor(c.model);
    Cartesian cart;
    cart.model = &model;
    cart.rotor = &rotor;
    cart.law = core::PenaltyLaw(model);
    cart.segment = c.segment;
    System sys;
    sys.cartesian = &cart;
    std::mt19937 rng(20261125);
    const double t = c.segment.start_time_s + 0.37;
    for (int trial = 0; trial < 30; ++trial) {
      const State x = random_state(rng, c.model);
      // The reduction is the kinematics' inverse (psi to within 2 pi).
      const core::Kinematics k = System::kinematics(x);
      State back = System::reduce(k);
      back[L::kAngle] += 2.0 * M_PI * std::round((x[L::kAngle] - back[L::kAngle]) / (2.0 * M_PI));
      EXPECT_LT((back - x).cwiseQuotient(steps()).cwiseAbs().maxCoeff(), 1e-3) << c.name << ", trial " << trial;
      for (int slip : {0, 1, -1}) {
        if (slip != 0 && !cart.law.has_friction()) continue;
        cart.mode = core::PenaltyMode{};
        cart.mode.pressed = true;
        cart.mode.slip = slip;
        std::string where;
        EXPECT_LE(worst_ratio(sys, x, steps(), t, &where), 1.0)
            << c.name << ", polar, trial " << trial << ", slip " << slip << ": " << where;
      }
    }
  }
};

TEST(PenaltyJacobian, ClosedFormMatchesDifferencesInEveryMode) {
  for (const Case& c : cases()) {
    if (c.model.stator_model == core::StatorModel::kRigid) {
      Checker<0>::run(c);
      PolarChecker<0>::run(c);
    } else {
      Checker<2>::run(c);
      PolarChecker<2>::run(c);
    }
  }
}

// The error of a polar state is measured as the Cartesian state's
// (PenaltyPolarSystem::error_norm): for a small error e of x0 the RMS of
// (y(x0 + e) - y(x0)) / (atol + rtol max(|y0|, |y1|)), y the Cartesian state.
TEST(PenaltyJacobian, PolarErrorIsTheCartesianStatesError) {
  using System = core::PenaltyPolarSystem<2, false>;
  using L = System::L;
  using FL = core::FreeLayout<2, false>;
  const core::ModelParameters p = test::paper_scene().model;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    const System::State x0 = PolarChecker<2>::random_state(rng, p);
    System::State e;
    // A thousandth of the difference steps: 1e-7 rad of psi, 1e-12 m of delta.
    for (int i = 0; i < L::kSize; ++i) e[i] = 1e-3 * unit(rng) * PolarChecker<2>::steps()[i];
    const System::State x1 = x0 + e;
    FL::State y0, y1;
    core::store_kinematics<2, false>(System::kinematics(x0), y0);
    core::store_kinematics<2, false>(System::kinematics(x1), y1);
    const double atol = 1e-12, rtol = 1e-9;
    const double cartesian =
        std::sqrt(((y1 - y0).array() / (atol + rtol * y0.array().abs().max(y1.array().abs()))).square().mean());
    System sys;
    // Linear in e to |e_psi| / 1 rad ~ 1e-7 relative; y1 - y0 rounds to
    // eps |y| / |y1 - y0| ~ 1e-8 (at 1e-6 of these steps it rounded to 1e-5).
    EXPECT_NEAR(sys.error_norm(e, x0, x1, atol, rtol), cartesian, 1e-6 * cartesian) << "trial " << trial;
  }
}

// A flexible rotor's penalty system (FlexibleRotor::add_free_jacobian: -K
// and -(C + w G) of the reduced rotor, the unbalances' rate): the seal rotor
// (its seal's circulatory kxy = -kyx: K not symmetric) with 8 planar modes on
// a rigid stator under gravity and on an elastic one far above its critical
// speed, and the anisotropic rig (kyy/kxx 115) with 20 planar modes at 400
// rad/s accelerating at 50 rad/s^2, where w G and its rate A G q' are large;
// every mode of the law at random states, the
// modal block's entries of the size a run reaches (xi ~ 1e-5 sqrt(kg) m).
// Differences of a linear block are exact but for rounding; the contact's
// rows are the Jeffcott's (Checker above).
template <int kStatorDof>
void check_flexible(const std::string& name, core::Scene s, const core::SpeedSegment& segment) {
  using System = core::PenaltySystem<kStatorDof, false, true, core::FlexibleRotor>;
  using L = typename System::L;
  using State = typename System::State;
  core::load_rotor(s);
  const core::FlexibleRotor rotor(s);
  const core::StationModel model(rotor.adopt(s.model));
  System sys;
  sys.model = &model;
  sys.rotor = &rotor;
  sys.law = core::PenaltyLaw(model);
  sys.segment = segment;
  const int n = rotor.modal_size();
  const double t = segment.start_time_s + 0.37;
  std::mt19937 rng(20261129);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), share(0.0, 1.0);
  State h(L::kSize + 2 * n);
  h.head(L::kDof).setConstant(kPositionStep_m);
  h.segment(L::kDof, L::kDof).setConstant(kVelocityStep_m_per_s);
  h.segment(L::kModal, n).setConstant(kPositionStep_m);
  h.tail(n).setConstant(kVelocityStep_m_per_s);
  std::vector<PenaltyMode> modes(4);
  modes[1].pressed = modes[2].pressed = modes[3].pressed = true;
  modes[2].slip = 1;
  modes[3].slip = -1;
  for (int trial = 0; trial < 12; ++trial) {
    State x = State::Zero(L::kSize + 2 * n);
    const double angle = M_PI * unit(rng);
    // Free states 1 um inside the bore: the pressed law extended there pulls
    // by k_c delta (1e3 N at 1e9 N/m), whose turning with the angle, over
    // the station's distance d, gives the differences a truncation of h^2
    // F / (6 m d^3); at d = C / 2 that reached 1.6e-6 of an entry.
    const double distance = s.model.clearance_m * (trial % 4 == 0 ? 0.95 : 1.0 + 0.5 * share(rng));
    const core::Vec2 stator = kStatorDof == 2 ? core::Vec2(1e-6 * unit(rng), 1e-6 * unit(rng)) : core::Vec2::Zero();
    x.template segment<2>(L::kRotorPos) = stator + distance * core::Vec2(std::cos(angle), std::sin(angle));
    x.template segment<2>(L::kRotorVel) = core::Vec2(1e-2 * unit(rng), 1e-2 * unit(rng));
    if constexpr (kStatorDof == 2) {
      x.template segment<2>(L::kStatorPos) = stator;
      x.template segment<2>(L::kStatorVel) = core::Vec2(1e-3 * unit(rng), 1e-3 * unit(rng));
    }
    for (int i = 0; i < n; ++i) {
      x[L::kModal + i] = 1e-5 * unit(rng);
      x[L::kModal + n + i] = 1e-2 * unit(rng);
    }
    for (const PenaltyMode& m : modes) {
      if (m.slip != 0 && !sys.law.has_friction()) continue;
      sys.mode = m;
      std::string where;
      EXPECT_LE(worst_ratio(sys, x, h, t, &where), 1.0)
          << name << ", trial " << trial << ", mode pressed " << m.pressed << " slip " << m.slip << ": " << where;
    }
    core::FreeFlightSystem<kStatorDof, false, core::FlexibleRotor> free;
    free.model = &model;
    free.rotor = &rotor;
    free.segment = segment;
    std::string where_free;
    EXPECT_LE(worst_ratio(free, x, h, t, &where_free), 1.0)
        << name << ", trial " << trial << ", free flight: " << where_free;
    core::IterationSystem<kStatorDof, false, core::FlexibleRotor> iteration;
    iteration.model = &model;
    iteration.rotor = &rotor;
    iteration.segment = segment;
    EXPECT_LE(worst_ratio(iteration, x, h, t, &where_free), 1.0)
        << name << ", trial " << trial << ", the iteration method's free flight: " << where_free;
    // The pressed mode in polar coordinates, the block beside them (steps:
    // PolarChecker's; the block's 1e-4 and 1e-1: every row is linear in the
    // block, so no step truncates). psi'' = (t . (a_r - a_s) - 2 delta'
    // psi') / delta sums terms of up to |a| / delta (a friction force of f
    // k_c delta over m delta, 1e7 rad/s^2) to a small result: their rounding
    // is that row's differences' floor (term_scale).
    if (distance < s.model.clearance_m) continue;
    using Polar = core::PenaltyPolarSystem<kStatorDof, false, true, core::FlexibleRotor>;
    using PL = typename Polar::L;
    Polar polar;
    polar.cartesian = &sys;
    polar.reserve(x.size());
    State xp = x;
    Polar::store(core::kinematics_of<kStatorDof, false, core::FlexibleRotor>(x), xp);
    State hp = h;
    hp.head(PL::kSize) = PolarChecker<kStatorDof>::steps();
    hp.segment(PL::kModal, n).setConstant(1e-4);
    hp.tail(n).setConstant(1e-1);
    for (int slip : {0, 1, -1}) {
      sys.mode = PenaltyMode{};
      sys.mode.pressed = true;
      sys.mode.slip = slip;
      const double delta = xp[PL::kDistance];
      const double terms =
          (rhs(sys, x, t).cwiseAbs().maxCoeff() + 2.0 * std::abs(xp[PL::kDistanceRate] * xp[PL::kAngleRate])) / delta;
      std::string where;
      EXPECT_LE(worst_ratio(polar, xp, hp, t, &where, terms, PL::kAngleRate), 1.0)
          << name << ", polar, trial " << trial << ", slip " << slip << ": " << where;
    }
  }
}

TEST(PenaltyJacobian, FlexibleRotorsClosedFormEqualsDifferences) {
  core::Scene seal = core::load_scene(test::source_path("config/seal_rub_runup.yaml"));
  seal.model.gravity_m_per_s2 = 9.81;
  check_flexible<0>("seal rotor, rigid stator, gravity", seal, {0.5, 3.0, 150.0, 70.0});
  seal.model.gravity_m_per_s2 = 0.0;
  seal.model.stator_model = core::StatorModel::kElastic;
  seal.model.friction_coefficient = 0.6;
  seal.model.restitution = 0.7;
  check_flexible<2>("seal rotor, elastic stator, far above critical", seal, {0.2, 10.0, 900.0, -40.0});
  core::Scene rig = seal;
  rig.model.stator_model = core::StatorModel::kRigid;
  rig.rotor.file = test::source_path("test/data/rotors/anisotropic_rig.yaml");
  rig.rotor.planar_modes = 20;
  rig.rotor.loaded.reset();
  check_flexible<0>("anisotropic rig, 20 planar modes", rig, {0.0, 1.0, 400.0, 50.0});
}

// The stiff integrator takes the closed form where the system gives it (6
// derivatives an accepted step, 5 a rejected one: 16 and 5 with
// differences), through the paper scene's first contacts (test_rodasp.cpp
// checks the runs themselves at every tolerance).
TEST(PenaltyJacobian, RodaspTakesTheClosedForm) {
  core::Scene s = test::with_method(test::paper_scene(), core::Method::kPenalty, 1e-6, 1e-9);
  s.solver.integrator = core::Integrator::kRosenbrock4;
  s.end_time_s = 1.3;
  const test::Run r = test::run(s);
  ASSERT_FALSE(r.result.failure.has_value()) << r.result.failure->message;
  const core::RunStats& st = r.result.stats;
  EXPECT_LE(static_cast<double>(st.rhs_evals) / static_cast<double>(st.steps + st.rejected_steps), 7.0);
}

// The pressed mode runs in polar coordinates: on the paper scene's sustained
// rub (to 2.0 s, rtol 1e-5) RODASP takes 1 118 steps there, and 28 074 with
// the pressed mode in Cartesian coordinates, whose stiff direction turns
// with the whirl inside each step (measured). The bound holds the polar
// path, with room for the controller's rounding.
TEST(PenaltyJacobian, SustainedRubStepsInPolarCoordinates) {
  core::Scene s = test::with_method(test::paper_scene(), core::Method::kPenalty, 1e-5, 1e-8);
  s.solver.integrator = core::Integrator::kRosenbrock4;
  s.end_time_s = 2.0;
  const test::Run r = test::run(s);
  ASSERT_FALSE(r.result.failure.has_value()) << r.result.failure->message;
  EXPECT_LT(r.result.stats.steps, 2000);
}

}  // namespace
}  // namespace rotor_rub
