// Periodic orbits in the frame turning with the shaft (turning_orbit.hpp) on
// the paper's scene (elastic stator, f = 0.1, no gravity): at 450 rad/s,
// where the full rub flutters, the rotor started just off it settles in 2000
// forcing periods on a partial rub that touches down once every 1.316
// forcing periods: quasi-periodic in the casing, periodic in the turning
// frame. Its trivial multiplier, its monodromy against the flow's
// differences, and the switching and iteration methods' runs, which come
// back to it turned by w T_r.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>

#include "rotor_rub_sim/core/full_rub_stability.hpp"
#include "rotor_rub_sim/core/turning_orbit.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

constexpr double kSpeed = 450.0;

// x with each planar pair turned by a (physical units: the same rotation).
Eigen::VectorXd turned(const Eigen::VectorXd& x, double a) {
  Eigen::VectorXd out = x;
  for (int i = 0; i + 1 < x.size(); i += 2) {
    out(i) = std::cos(a) * x(i) - std::sin(a) * x(i + 1);
    out(i + 1) = std::sin(a) * x(i) + std::cos(a) * x(i + 1);
  }
  return out;
}

// The settled motion's guess: from the full rub at 450 rad/s with the rotor
// 0.1 % off the bore, 2000 forcing periods of the flow.
const core::TurningGuess& settled_guess() {
  static const core::TurningGuess guess = [] {
    const core::ModelParameters p = test::paper_scene().model;
    const auto rubs = core::full_rub_stability(p, kSpeed);
    const std::complex<double> i_w(0.0, kSpeed), z = rubs.front().station_m, zs = rubs.front().stator_m;
    Eigen::VectorXd x(8);
    x << 0.999 * z.real(), 0.999 * z.imag(), zs.real(), zs.imag(), (i_w * z).real(), (i_w * z).imag(),
        (i_w * zs).real(), (i_w * zs).imag();
    const double settled_s = 2000.0 * 2.0 * M_PI / kSpeed;
    x = core::orbit_flow(p, kSpeed, x, 0.0, settled_s).state;
    return core::turning_orbit_guess(p, kSpeed, x, settled_s, 100);
  }();
  return guess;
}

}  // namespace

// The orbit: one touchdown and one lift-off per turning period, stable; its
// trivial multiplier is 1 to kTrivial (the flow's direction is an exact
// eigenvector of R(-w T_r) Phi: what is left is the monodromy's error,
// measured 6e-12); the switching and iteration methods started on it
// (turned back to the spin angle 0) return to it turned by w T_r after T_r,
// to kMethods of C and C w (their rtol 1e-10 over 1.3 forcing periods:
// measured 1.8e-10 and 2.7e-10).
TEST(TurningOrbit, ThePaperScenesPartialRubPastTheFlutter) {
  constexpr double kTrivial = 1e-8;
  constexpr double kMethods = 1e-9;
  const core::ModelParameters p = test::paper_scene().model;
  const double w = kSpeed;
  const core::PeriodicOrbit o = core::find_turning_orbit(p, w, settled_guess());
  std::printf(
      "turning orbit at %g rad/s: T_r = %.12g s (%.6f forcing periods), trivial multiplier 1 %+.1e, the "
      "largest other %.9f\n",
      w, o.period_s, o.period_s * w / (2.0 * M_PI), o.trivial_multiplier - 1.0, std::abs(o.multipliers.front()));
  ASSERT_TRUE(o.turning);
  std::printf("Newton: %d iterations, residual %.1e of C\n", o.newton_iterations, o.residual);
  EXPECT_NEAR(o.trivial_multiplier, 1.0, kTrivial);
  EXPECT_EQ(o.multipliers.size(), 7u);
  EXPECT_TRUE(o.stable());
  ASSERT_EQ(o.events.size(), 2u);
  EXPECT_EQ(o.events[0].kind, core::OrbitEvent::Kind::kTouchdown);  // the section in the flight before it
  EXPECT_EQ(o.events[1].kind, core::OrbitEvent::Kind::kLiftOff);
  EXPECT_GT(o.period_s * w / (2.0 * M_PI), 1.3);
  EXPECT_LT(o.period_s * w / (2.0 * M_PI), 1.33);
  const Eigen::VectorXd start = turned(o.state, -o.section_angle_rad);
  for (const core::Method method : {core::Method::kSwitching, core::Method::kIteration}) {
    const Eigen::VectorXd x = test::method_states(method, p, w, start, {o.period_s}).front();
    const double back = test::scaled_norm(x - turned(start, w * o.period_s), p, w);
    std::printf("%s: back on the turning orbit after T_r to %.2e of C\n", core::to_string(method), back);
    EXPECT_LT(back, kMethods);
  }
}

// Newton's Jacobian, its period column included: from the guess with its
// period 1e-3 off and its state 1e-4 of C off, Newton converges in at most
// kIterations (quadratically) to the same orbit, to kSame of its period.
TEST(TurningOrbit, NewtonConvergesFromAnOffGuess) {
  constexpr int kIterations = 6;
  constexpr double kSame = 1e-10;
  const core::ModelParameters p = test::paper_scene().model;
  const core::PeriodicOrbit o = core::find_turning_orbit(p, kSpeed, settled_guess());
  core::TurningGuess off = settled_guess();
  off.period_s *= 1.0 + 1e-3;
  off.state(0) += 1e-4 * p.clearance_m;
  const core::PeriodicOrbit again = core::find_turning_orbit(p, kSpeed, off);
  std::printf("from the off guess: %d Newton iterations, T_r %.12g s against %.12g s\n", again.newton_iterations,
              again.period_s, o.period_s);
  EXPECT_LE(again.newton_iterations, kIterations);
  EXPECT_NEAR(again.period_s, o.period_s, kSame * o.period_s);
}

// The monodromy R(-w T_r) Phi is the derivative of the turning frame's map
// over T_r (T_r held): central differences of shots at the tolerance 1e-13
// of step 3e-6 in C and C w (ThroughStickPhasesTheMonodromyIsTheFlowsDerivative's
// reasons: the contact phase is not affine), to kDifference (measured
// 3.1e-10).
TEST(TurningOrbit, TheMonodromyIsTheTurningMapsDerivative) {
  constexpr double kDifference = 1e-8;
  constexpr double kStep = 3e-6;
  const core::ModelParameters p = test::paper_scene().model;
  const double w = kSpeed;
  const core::PeriodicOrbit o = core::find_turning_orbit(p, w, settled_guess());
  core::OrbitSettings fine;
  fine.tolerance = 1e-13;
  const double t0 = o.section_angle_rad / w;
  Eigen::VectorXd scale(8);
  scale.head(4).setConstant(p.clearance_m);
  scale.tail(4).setConstant(p.clearance_m * w);
  Eigen::MatrixXd diff(8, 8);
  for (int i = 0; i < 8; ++i) {
    const Eigen::VectorXd step = kStep * Eigen::VectorXd::Unit(8, i).cwiseProduct(scale);
    const Eigen::VectorXd up = core::orbit_flow(p, w, o.state + step, t0, t0 + o.period_s, fine).state;
    const Eigen::VectorXd down = core::orbit_flow(p, w, o.state - step, t0, t0 + o.period_s, fine).state;
    diff.col(i) = turned(up - down, -w * o.period_s).cwiseQuotient(scale) / (2.0 * kStep);
  }
  const double off = (diff - o.monodromy).cwiseAbs().maxCoeff();
  std::printf("the turning monodromy against the flow's differences: %.2e\n", off);
  EXPECT_LT(off, kDifference);
}

// What the turning frame cannot take is said: gravity, an offset stator (the
// scene is not autonomous there), a guess of no period, a motion without
// impacts to find one from. Each is refused before any shot, so the guess
// need not be the orbit's (and the test stays short enough for the
// sanitized run, test/sanitize_skip.txt).
TEST(TurningOrbit, BadInputIsAClearError) {
  const core::ModelParameters p = test::paper_scene().model;
  core::TurningGuess guess;
  guess.state = Eigen::VectorXd::Zero(8);
  guess.period_s = 2.0 * M_PI / kSpeed;
  for (const char* key : {"gravity_m_per_s2", "stator_offset_x_m"}) {
    core::ModelParameters q = p;
    (std::string(key) == "gravity_m_per_s2" ? q.gravity_m_per_s2 : q.stator_offset_x_m) = 1e-4;
    try {
      core::find_turning_orbit(q, kSpeed, guess);
      ADD_FAILURE() << key;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
  guess.period_s = 0.0;
  EXPECT_THROW(core::find_turning_orbit(p, kSpeed, guess), std::invalid_argument);
  // From rest at 450 rad/s the rotor's transient may touch the bore, but it
  // settles without contact: no impacts repeat.
  try {
    core::turning_orbit_guess(p, kSpeed, Eigen::VectorXd::Zero(8), 0.0, 50);
    ADD_FAILURE() << "a guess from a motion without repeating impacts";
  } catch (const core::OrbitError& e) {
    EXPECT_NE(std::string(e.what()).find("do not repeat"), std::string::npos) << e.what();
  }
}
