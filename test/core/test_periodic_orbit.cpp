// Periodic orbits and their Floquet multipliers (periodic_orbit.hpp): the
// free rotor's exponentials, the full rub's eigenvalues in the turning
// frame, the flow's own derivative by differences through impacts, contact
// phases and lift-offs, and the switching and iteration methods' runs, which
// come back to the orbit after its period.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/full_rub_stability.hpp"
#include "rotor_rub_sim/core/model.hpp"
#include "rotor_rub_sim/core/periodic_orbit.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"
#include "test_support.hpp"

using namespace rotor_rub;
using cd = std::complex<double>;

namespace {

// The paper's rotor on a rigid stator under gravity (its sag 1.64 mm of the
// 2 mm clearance), where the unbalance's orbit reaches the bore's bottom
// once a revolution: at 60 rad/s with e = 0.5 one impact per period; at 70
// rad/s, plastic, an impact, then a touchdown, a contact and a lift-off.
core::ModelParameters sagging(double restitution) {
  core::ModelParameters p = test::paper_model(core::StatorModel::kRigid, 0.1);
  p.gravity_m_per_s2 = 9.81;
  p.restitution = restitution;
  return p;
}

// A thin shaft (R_r = C: a 4 mm pin in its 2 mm clearance) with dry friction
// f = 1, plastic, otherwise as sagging(): at 110 rad/s it stays on the
// bore's bottom, sticking (rolling back on the bore) and slipping twice a
// revolution.
core::ModelParameters thin_shaft() {
  core::ModelParameters p = sagging(0.0);
  p.rotor_radius_m = p.clearance_m;
  p.friction_coefficient = 1.0;
  return p;
}
constexpr double kThinShaftSpeed = 110.0;

// A thin shaft with f = 0.5 and e = 0.3: at 115 rad/s, once a revolution, a
// cascade of ten rebounds settles onto the bore's bottom, the contact
// sticks, slips and lifts off.
core::ModelParameters bouncing_shaft() {
  core::ModelParameters p = thin_shaft();
  p.friction_coefficient = 0.5;
  p.restitution = 0.3;
  return p;
}
constexpr double kBouncingShaftSpeed = 115.0;

// The largest distance between each of `expected` and its nearest in `got`.
double worst_match(const std::vector<cd>& expected, const std::vector<cd>& got) {
  double worst = 0.0;
  for (const cd& e : expected) {
    double best = INFINITY;
    for (const cd& g : got) best = std::min(best, std::abs(g - e));
    worst = std::max(worst, best);
  }
  return worst;
}

std::vector<cd> eigenvalues(const Eigen::MatrixXd& m) {
  const Eigen::EigenSolver<Eigen::MatrixXd> es(m, false);
  return {es.eigenvalues().data(), es.eigenvalues().data() + m.rows()};
}

// The Newton tolerance (in C and C w) bounds a fixed point's error by the
// residual over 1 - |mu| (here at least 0.1).
constexpr double kFixedPoint = 1e-8;

}  // namespace

// Without contact (C = 1 m) the flow is linear: the orbit is the unbalance's
// steady response about the sag, and the multipliers are exp(lambda T) of
// the free rotor's and stator's eigenvalues (m l^2 + c l + k = 0, each twice)
// to kExponentials: the integrator's tolerance 1e-11, relative.
TEST(PeriodicOrbit, WithoutContactTheMultipliersAreTheFreeRotorsExponentials) {
  constexpr double kExponentials = 1e-10;
  for (double w : {50.0, 300.0}) {
    core::ModelParameters p = test::paper_model(core::StatorModel::kElastic, 0.1);
    p.clearance_m = 1.0;
    p.gravity_m_per_s2 = 9.81;
    const core::PeriodicOrbit o = core::find_periodic_orbit(p, w, Eigen::VectorXd::Zero(8));
    const double period = 2.0 * M_PI / w;
    std::vector<cd> expected;
    for (const auto& [m, c, k] :
         {std::tuple{p.rotor_mass_kg, p.rotor_damping_N_s_per_m, p.rotor_stiffness_N_per_m},
          std::tuple{p.stator_mass_kg, p.stator_damping_N_s_per_m, p.stator_stiffness_N_per_m}}) {
      const cd root = std::sqrt(cd(c * c - 4.0 * m * k));
      for (const cd l : {(-c + root) / (2.0 * m), (-c - root) / (2.0 * m)}) {
        expected.push_back(std::exp(l * period));
        expected.push_back(std::exp(l * period));
      }
    }
    ASSERT_EQ(o.multipliers.size(), 8u);
    EXPECT_LT(worst_match(expected, o.multipliers), kExponentials) << w;
    EXPECT_TRUE(o.stable());
    EXPECT_TRUE(o.events.empty());
    // x + i y of the rotor: m e w^2 / (k - m w^2 + i c w) below the sag.
    const double m = p.rotor_mass_kg;
    const cd z =
        m * p.eccentricity_m * w * w / cd(p.rotor_stiffness_N_per_m - m * w * w, p.rotor_damping_N_s_per_m * w) -
        cd(0.0, m * p.gravity_m_per_s2 / p.rotor_stiffness_N_per_m);
    const cd v = cd(0.0, w) * (z + cd(0.0, m * p.gravity_m_per_s2 / p.rotor_stiffness_N_per_m));
    Eigen::VectorXd x = Eigen::VectorXd::Zero(8);
    x << z.real(), z.imag(), 0.0, -p.stator_mass_kg * p.gravity_m_per_s2 / p.stator_stiffness_N_per_m, v.real(),
        v.imag(), 0.0, 0.0;
    EXPECT_LT(test::scaled_norm(o.state - x, p, w), kFixedPoint) << w;
  }
}

// The full rub is an orbit that stays in contact: its multipliers on the
// bore's tangent space are exp(lambda T) of the turning frame's eigenvalues
// (full_rub_stability.hpp; the turning frame's rotation is the identity
// after a period), both branches, to kTurningFrame of the largest (measured
// 7e-11 to 5.6e-10: the contact field's central differences, 1e-10, and the
// integrator's 1e-11 over a period).
TEST(PeriodicOrbit, TheFullRubsMultipliersAreItsEigenvaluesExponentials) {
  constexpr double kTurningFrame = 1e-8;
  struct Case {
    core::StatorModel stator;
    double w;
  };
  for (const Case& c : {Case{core::StatorModel::kRigid, 300.0}, Case{core::StatorModel::kElastic, 120.0},
                        Case{core::StatorModel::kElastic, 300.0}}) {
    const core::ModelParameters p = test::paper_model(c.stator, 0.1);
    const auto branches = core::full_rub_stability(p, c.w);
    ASSERT_EQ(branches.size(), 2u);
    for (const core::FullRubStability& b : branches) {
      const int n = c.stator == core::StatorModel::kRigid ? 4 : 8, v = n / 2;
      Eigen::VectorXd guess = Eigen::VectorXd::Zero(n);
      const cd vr = cd(0.0, c.w) * b.station_m, vs = cd(0.0, c.w) * b.stator_m;
      guess.head<2>() << b.station_m.real(), b.station_m.imag();
      guess.segment<2>(v) << vr.real(), vr.imag();
      if (n == 8) {
        guess.segment<2>(2) << b.stator_m.real(), b.stator_m.imag();
        guess.segment<2>(v + 2) << vs.real(), vs.imag();
      }
      const core::PeriodicOrbit o = core::find_periodic_orbit(p, c.w, guess);
      std::vector<cd> expected;
      for (const cd& l : b.eigenvalues) expected.push_back(std::exp(l * o.period_s));
      SCOPED_TRACE(std::string(core::to_string(c.stator)) + " w " + std::to_string(c.w));
      EXPECT_TRUE(o.starts_in_contact);
      EXPECT_TRUE(o.events.empty());
      ASSERT_EQ(o.multipliers.size(), b.eigenvalues.size());
      const double off = worst_match(expected, o.multipliers) / std::abs(expected.front());
      std::printf("full rub %s w %g: |mu| max %.6f, off exp(lambda T) by %.2e of it\n", core::to_string(c.stator), c.w,
                  std::abs(o.multipliers.front()), off);
      EXPECT_LT(off, kTurningFrame);
      EXPECT_EQ(o.stable(), b.stable());
      EXPECT_LT(test::scaled_norm(o.state - guess, p, c.w), kFixedPoint);
    }
  }
}

// Through impacts, a contact phase and its lift-off, the monodromy (in C and
// C w) is the flow's derivative: central differences of the flow over a
// period (step 1e-6 in C and C w) agree to kDifference (measured 2.6e-10 to
// 4.7e-10: the integrator's error is smooth in the start and cancels in the
// difference, which leaves the step's square and the rounding over the
// step). A plastic impact leaves a multiplier 0, a touchdown into contact
// another, to kZero (the contact field's central differences, 1e-10).
TEST(PeriodicOrbit, TheMonodromyIsTheFlowsDerivative) {
  constexpr double kDifference = 1e-8;
  constexpr double kZero = 1e-8;
  struct Case {
    double restitution, w;
    std::vector<core::OrbitEvent::Kind> events;
    int zeros;
  };
  using K = core::OrbitEvent::Kind;
  for (const Case& c : {Case{0.5, 60.0, {K::kImpact}, 0}, Case{0.0, 60.0, {K::kImpact}, 1},
                        Case{0.0, 70.0, {K::kImpact, K::kTouchdown, K::kLiftOff}, 2}}) {
    const core::ModelParameters p = sagging(c.restitution);
    const core::PeriodicOrbit o = core::find_periodic_orbit(p, c.w, core::settled_state(p, c.w, 100));
    SCOPED_TRACE("e " + std::to_string(c.restitution) + " w " + std::to_string(c.w));
    ASSERT_EQ(o.events.size(), c.events.size());
    for (std::size_t j = 0; j < c.events.size(); ++j) EXPECT_EQ(o.events[j].kind, c.events[j]);
    EXPECT_TRUE(o.stable());
    Eigen::MatrixXd diff(4, 4);
    for (int i = 0; i < 4; ++i) {
      Eigen::VectorXd step = Eigen::VectorXd::Zero(4);
      step(i) = 1e-6 * p.clearance_m * (i < 2 ? 1.0 : c.w);
      diff.col(i) = (core::orbit_flow(p, c.w, o.state + step, 0.0, o.period_s).state -
                     core::orbit_flow(p, c.w, o.state - step, 0.0, o.period_s).state) /
                    2.0;
      diff.col(i).head(2) /= p.clearance_m;
      diff.col(i).tail(2) /= p.clearance_m * c.w;
      diff.col(i) /= 1e-6;
    }
    const double off = (diff - o.monodromy).cwiseAbs().maxCoeff();
    std::printf("e %g w %g: the monodromy against the flow's differences: %.2e\n", c.restitution, c.w, off);
    EXPECT_LT(off, kDifference);
    EXPECT_LT(worst_match(eigenvalues(diff), o.multipliers), kDifference);
    int zeros = 0;
    for (const cd& mu : o.multipliers) zeros += std::abs(mu) < kZero;
    EXPECT_EQ(zeros, c.zeros);
  }
}

// Through sticking phases: the thin shaft's orbit in contact throughout,
// stick, slip, stick, slip, on the rigid stator at 110 rad/s (stable) and on
// the paper's elastic stator at 105 rad/s (unstable: a multiplier -1.34).
// On the bore's tangent space (a section in the middle of a slip, n - 2
// dimensions) and on the stick's (in the middle of a stick, n - 3) the
// monodromy is the flow's derivative to kDifference: central differences
// along the tangent basis of step 3e-6 of shots at the tolerance 1e-13 (the
// contact's flow is not affine: the differences carry the integrator's
// error over the step, 1e-7 at the default 1e-11, and the step's square
// times the flow's curvature, 4e-7 at a step of 3e-5 on the elastic
// stator; measured 1.0e-9 to 6.3e-9). Entering a stick leaves a multiplier 0 on the bore's tangent
// space (the slip dies), and both sections' Poincare maps share the others
// (conjugate maps).
TEST(PeriodicOrbit, ThroughStickPhasesTheMonodromyIsTheFlowsDerivative) {
  constexpr double kDifference = 1e-8;
  constexpr double kZero = 1e-8;  // a saltation's rank: 0 to the contact field's differences (measured 1e-12 to 1e-10)
  constexpr double kStep = 3e-6;
  using K = core::OrbitEvent::Kind;
  core::ModelParameters elastic = thin_shaft();
  elastic.stator_model = core::StatorModel::kElastic;
  struct Case {
    core::ModelParameters p;
    double w;
    bool stable;
  };
  for (const Case& k : {Case{thin_shaft(), kThinShaftSpeed, true}, Case{elastic, 105.0, false}}) {
    const core::ModelParameters& p = k.p;
    const double w = k.w;
    const int n = p.stator_model == core::StatorModel::kElastic ? 8 : 4;
    const core::PeriodicOrbit o = core::find_periodic_orbit(p, w, core::settled_state(p, w, 400));
    ASSERT_EQ(o.events.size(), 4u) << w;
    for (std::size_t j = 0; j < 4; ++j) EXPECT_EQ(o.events[j].kind, j % 2 == 0 ? K::kStick : K::kSlip);
    // Sections in the middle of the first stick and of the slip after it.
    std::vector<core::PeriodicOrbit> orbits;
    for (const std::size_t j : {0, 1}) {
      core::OrbitSettings s;
      const double t0 = 0.5 * (o.events[j].time_s + o.events[j + 1].time_s);
      s.section_angle_rad = w * t0;
      orbits.push_back(core::find_periodic_orbit(p, w, core::orbit_flow(p, w, o.state, 0.0, t0).state, s));
      EXPECT_TRUE(orbits.back().starts_in_contact);
      EXPECT_EQ(orbits.back().starts_in_stick, j == 0);
    }
    core::OrbitSettings fine;
    fine.tolerance = 1e-13;
    Eigen::VectorXd scale(n);  // from y (in C and C w) to x
    scale.head(n / 2).setConstant(p.clearance_m);
    scale.tail(n / 2).setConstant(p.clearance_m * w);
    for (const core::PeriodicOrbit& c : orbits) {
      const Eigen::MatrixXd& basis = c.tangent_basis;
      const int m = static_cast<int>(basis.cols());
      ASSERT_EQ(m, n - (c.starts_in_stick ? 3 : 2));
      const double t0 = c.section_angle_rad / w;
      Eigen::MatrixXd diff(m, m);
      for (int i = 0; i < m; ++i) {
        const Eigen::VectorXd step = kStep * basis.col(i).cwiseProduct(scale);
        const Eigen::VectorXd up = core::orbit_flow(p, w, c.state + step, t0, t0 + c.period_s, fine).state;
        const Eigen::VectorXd down = core::orbit_flow(p, w, c.state - step, t0, t0 + c.period_s, fine).state;
        diff.col(i) = basis.transpose() * (up - down).cwiseQuotient(scale) / (2.0 * kStep);
      }
      const double off = (diff - c.monodromy).cwiseAbs().maxCoeff();
      std::printf("thin shaft, %s stator, section %.3f rad (%s): the monodromy against the flow's differences: %.2e\n",
                  core::to_string(p.stator_model), c.section_angle_rad, c.starts_in_stick ? "stick" : "slip", off);
      EXPECT_LT(off, kDifference);
      EXPECT_LT(worst_match(eigenvalues(diff), c.multipliers), kDifference);
      EXPECT_EQ(c.stable(), k.stable);
    }
    const core::PeriodicOrbit& slipping = orbits[1];
    EXPECT_LT(std::abs(slipping.multipliers.back()), kZero);
    EXPECT_LT(std::abs(slipping.multipliers.front() - orbits[0].multipliers.front()), kDifference);
    std::printf("thin shaft, %s stator, at %g rad/s: the largest multiplier %.9f, the smallest %.1e\n",
                core::to_string(p.stator_model), w, std::abs(slipping.multipliers.front()),
                std::abs(slipping.multipliers.back()));
  }
}

// A partial rub with a sticking phase: the bouncing shaft's orbit (impacts,
// a touchdown, a stick, a slip, a lift-off) at a section in free flight; its
// monodromy is the flow's derivative to kDifference: central differences of
// step 3e-6 at the tolerance 1e-13, as above, against a monodromy whose
// cascade's slowest impacts (closing at 1e-6 to 5e-6 m/s) take their jump's
// differences at a hundredth of their closing velocity, with a rounding of
// 2e-9 each (measured 3.4e-9 to 6.5e-9 at steps 3e-6 to 3e-5). Two
// multipliers 0 come from the touchdown, one more from the stick's entry.
TEST(PeriodicOrbit, APartialRubThatSticks) {
  constexpr double kDifference = 2e-8;
  constexpr double kZero = 1e-8;  // as in ThroughStickPhasesTheMonodromyIsTheFlowsDerivative
  constexpr double kStep = 3e-6;
  using K = core::OrbitEvent::Kind;
  const core::ModelParameters p = bouncing_shaft();
  const double w = kBouncingShaftSpeed;
  const core::PeriodicOrbit o = core::find_periodic_orbit(p, w, core::settled_state(p, w, 400));
  std::vector<K> kinds;
  for (const core::OrbitEvent& e : o.events) kinds.push_back(e.kind);
  ASSERT_EQ(kinds.size(), 14u);
  EXPECT_EQ(kinds.front(), K::kLiftOff);
  for (std::size_t j = 1; j <= 10; ++j) EXPECT_EQ(kinds[j], K::kImpact) << j;
  EXPECT_EQ(kinds[11], K::kTouchdown);
  EXPECT_EQ(kinds[12], K::kStick);
  EXPECT_EQ(kinds[13], K::kSlip);
  // The section in the middle of the flight.
  core::OrbitSettings s;
  const double t0 = 0.5 * (o.events[0].time_s + o.events[1].time_s);
  s.section_angle_rad = w * t0;
  const core::PeriodicOrbit f = core::find_periodic_orbit(p, w, core::orbit_flow(p, w, o.state, 0.0, t0).state, s);
  ASSERT_FALSE(f.starts_in_contact);
  core::OrbitSettings fine = s;
  fine.tolerance = 1e-13;
  Eigen::VectorXd scale(4);  // from y (in C and C w) to x
  scale << p.clearance_m, p.clearance_m, p.clearance_m * w, p.clearance_m * w;
  Eigen::MatrixXd diff(4, 4);
  for (int i = 0; i < 4; ++i) {
    const Eigen::VectorXd step = kStep * Eigen::VectorXd::Unit(4, i).cwiseProduct(scale);
    const Eigen::VectorXd up = core::orbit_flow(p, w, f.state + step, t0, t0 + f.period_s, fine).state;
    const Eigen::VectorXd down = core::orbit_flow(p, w, f.state - step, t0, t0 + f.period_s, fine).state;
    diff.col(i) = (up - down).cwiseQuotient(scale) / (2.0 * kStep);
  }
  const double off = (diff - f.monodromy).cwiseAbs().maxCoeff();
  std::printf("bouncing shaft at %g rad/s: the monodromy against the flow's differences: %.2e; multiplier %.9f\n", w,
              off, std::abs(f.multipliers[0]));
  EXPECT_LT(off, kDifference);
  EXPECT_TRUE(f.stable());
  int zeros = 0;
  for (const cd& mu : f.multipliers) zeros += std::abs(mu) < kZero;
  EXPECT_EQ(zeros, 3);
  EXPECT_LT(std::abs(f.multipliers[0] - o.multipliers[0]), kDifference);
}

// The switching and iteration methods' stick and slip (contact_law.hpp's,
// located by their own scans) started on the thin shaft's and the bouncing
// shaft's orbits come back to them after their period: to kMethods of C and
// C w (their rtol 1e-10 over a period: measured 1.0e-10 and 1.6e-10), and
// through the bouncing shaft's ten impacts to kCascade (ShotsFollowEveryRebound's:
// measured 7.4e-10 and 8.7e-10).
TEST(PeriodicOrbit, ThroughStickPhasesTheMethodsComeBackToTheOrbit) {
  constexpr double kMethods = 1e-9;
  constexpr double kCascade = 1e-8;
  struct Case {
    core::ModelParameters p;
    double w, tolerance;
  };
  for (const Case& c :
       {Case{thin_shaft(), kThinShaftSpeed, kMethods}, Case{bouncing_shaft(), kBouncingShaftSpeed, kCascade}}) {
    const core::PeriodicOrbit o = core::find_periodic_orbit(c.p, c.w, core::settled_state(c.p, c.w, 400));
    for (const core::Method method : {core::Method::kSwitching, core::Method::kIteration}) {
      const Eigen::VectorXd x = test::method_states(method, c.p, c.w, o.state, {o.period_s}).front();
      const double back = test::scaled_norm(x - o.state, c.p, c.w);
      std::printf("%s at %g rad/s: back on the orbit after a period to %.2e of C\n", core::to_string(method), c.w,
                  back);
      EXPECT_LT(back, c.tolerance);
    }
  }
}

// The switching and iteration methods started on an orbit come back to it
// after its period, to kMethods of C and C w (measured 4.5e-12 to 7.6e-11:
// their rtol 1e-10 over a period), through impacts, contact phases and the
// full rub (and stick-slip: ThroughStickPhasesTheMethodsComeBackToTheOrbit); a period-2 shot of a period-1 orbit has
// the squares of its multipliers.
TEST(PeriodicOrbit, TheRigidMethodsComeBackToTheOrbit) {
  constexpr double kMethods = 1e-9;
  constexpr double kSquares = 1e-9;
  struct Case {
    core::ModelParameters p;
    double w;
  };
  core::ModelParameters full_rub = test::paper_model(core::StatorModel::kElastic, 0.1);
  for (const Case& c : {Case{sagging(0.5), 60.0}, Case{sagging(0.0), 70.0}, Case{full_rub, 120.0}}) {
    const Eigen::VectorXd start = core::settled_state(c.p, c.w, 200);
    const core::PeriodicOrbit o = core::find_periodic_orbit(c.p, c.w, start);
    for (const core::Method method : {core::Method::kSwitching, core::Method::kIteration}) {
      const Eigen::VectorXd x = test::method_states(method, c.p, c.w, o.state, {o.period_s}).front();
      const double back = test::scaled_norm(x - o.state, c.p, c.w);
      std::printf("%s w %g: back on the orbit after a period to %.2e of C\n", core::to_string(method), c.w, back);
      EXPECT_LT(back, kMethods);
    }
    core::OrbitSettings twice;
    twice.periods = 2;
    const core::PeriodicOrbit o2 = core::find_periodic_orbit(c.p, c.w, o.state, twice);
    std::vector<cd> squares;
    for (const cd& mu : o.multipliers) squares.push_back(mu * mu);
    EXPECT_LT(worst_match(squares, o2.multipliers), kSquares) << c.w;
    EXPECT_EQ(o2.events.size(), 2 * o.events.size());
  }
}

// What the shooting cannot do is said, never drawn: a guess far from any
// orbit, a grazing orbit, a chattering shot, a motor drive.
TEST(PeriodicOrbit, BadStartsAreClearErrors) {
  const core::ModelParameters p = sagging(0.0);
  // Without contact the rotor circles its sag s = m g / k at the radius A of
  // the unbalance's response: its farthest point from the bore's centre is
  // s + A below it. A bore 1e-12 beyond it is missed by a hair, one 1e-14
  // short of it is touched at 1e-7 of C w.
  const double w = 40.0, m = p.rotor_mass_kg;
  const double reach =
      m * p.gravity_m_per_s2 / p.rotor_stiffness_N_per_m +
      std::abs(m * p.eccentricity_m * w * w / cd(p.rotor_stiffness_N_per_m - m * w * w, p.rotor_damping_N_s_per_m * w));
  core::ModelParameters apart = p;
  apart.clearance_m = 1.0;
  const Eigen::VectorXd guess = core::find_periodic_orbit(apart, w, Eigen::VectorXd::Zero(4)).state;
  for (double margin : {1e-12, -1e-14}) {
    core::ModelParameters g = p;
    g.clearance_m = reach * (1.0 + margin);
    try {
      core::find_periodic_orbit(g, w, guess);
      ADD_FAILURE() << "a grazing orbit passed: margin " << margin;
    } catch (const core::OrbitError& e) {
      EXPECT_NE(std::string(e.what()).find("graz"), std::string::npos) << e.what();
    }
  }
  core::OrbitSettings one_event;
  one_event.max_events = 1;
  EXPECT_THROW(core::find_periodic_orbit(p, 70.0, core::settled_state(p, 70.0, 100), one_event), core::OrbitError);
  // A guess on the bore where the full rub does not hold (p: 70 rad/s).
  Eigen::VectorXd on_bore = Eigen::VectorXd::Zero(4);
  on_bore << 0.0, -p.clearance_m, 70.0 * p.clearance_m, 0.0;
  EXPECT_THROW(core::find_periodic_orbit(p, 70.0, on_bore), core::OrbitError);
  core::ModelParameters motor = p;
  motor.drive_model = core::DriveModel::kMotor;
  EXPECT_THROW(core::find_periodic_orbit(motor, 70.0, on_bore), std::invalid_argument);
  EXPECT_THROW(core::find_periodic_orbit(p, -1.0, on_bore), std::invalid_argument);
  EXPECT_THROW(core::find_periodic_orbit(p, 70.0, Eigen::VectorXd::Zero(8)), std::invalid_argument);
}

// Cascades of rebounds on the bore's bottom (the horizontal rotor at 66.5
// and 66.875 rad/s from rest): the last rebounds fly for less than a step
// (at 66.5 rad/s 1.4 microseconds, shorter than the shot's first probe of a
// step); each is found (a probe at
// its apex, one past its return), and the shot agrees with the switching
// method (ReboundCascade's scene) over seven periods through every impact, to
// kCascade of C and C w (the methods' tolerances, 1e-11 and 1e-10, grown
// through the cascades' impacts: measured 9.5e-11 and 2.4e-10).
TEST(PeriodicOrbit, ShotsFollowEveryRebound) {
  constexpr double kCascade = 1e-8;
  constexpr int kCascadePeriods = 7;
  for (double w : {66.5, 66.875}) {
    const core::ModelParameters p = sagging(0.5);
    const Eigen::VectorXd x = Eigen::VectorXd::Zero(4);  // from rest: the transient's cascades
    const double period = kCascadePeriods * 2.0 * M_PI / w;
    const core::OrbitFlow f = core::orbit_flow(p, w, x, 0.0, period);
    int impacts = 0;
    double slowest = INFINITY, shortest = INFINITY;
    for (std::size_t j = 0; j < f.events.size(); ++j) {
      const core::OrbitEvent& e = f.events[j];
      impacts += e.kind == core::OrbitEvent::Kind::kImpact;
      if (e.kind != core::OrbitEvent::Kind::kLiftOff) slowest = std::min(slowest, e.normal_velocity_m_per_s);
      if (j > 0) shortest = std::min(shortest, e.time_s - f.events[j - 1].time_s);
    }
    const Eigen::VectorXd m = test::method_states(core::Method::kSwitching, p, w, x, {period}).front();
    const double off = test::scaled_norm(m - f.state, p, w);
    std::printf(
        "w %g: %zu events (%d impacts, the slowest closing at %.3g m/s, the shortest flight %.3g s); the switching "
        "method %.2e of C away\n",
        w, f.events.size(), impacts, slowest, shortest, off);
    EXPECT_GT(impacts, 20);
    EXPECT_LT(shortest, 2.0 * M_PI / w / core::OrbitSettings().min_steps_per_period);  // shorter than a step
    EXPECT_GT(slowest, 0.0);
    EXPECT_LT(off, kCascade);
  }
}
