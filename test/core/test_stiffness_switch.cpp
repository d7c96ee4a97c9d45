// dop853_rosenbrock4's free-flight integrator (dense_stiffness_switch.hpp) on
// two uncoupled oscillators, a slow one that rings and a fast one:
// x1'' + x1 = 0 from x1 = 1, so x1 = cos t; x2'' + 2 z w x2' + w^2 x2 = F cos(v t)
// from its forced response's own state, so x2 = F cos(v t) / (w^2 - v^2)
// exactly (undamped), plus a free part of 1e-14 where it is started off that
// state. A fast w (a flexible rotor's highest mode kept) holds dop853's steps
// to its stability, h w <= 6, however small x2 is; exactly 0, x2 would
// give dop853 no error to see.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "integrators/dense_high_order.hpp"
#include "integrators/dense_stiffness_switch.hpp"

namespace rotor_rub {
namespace {

using State = Eigen::Vector4d;

struct TwoOscillators {
  static constexpr bool kAnalyticJacobian = false, kSecondOrderJacobian = false, kOwnErrorNorm = false;
  static constexpr bool kOwnEndDerivatives = false;
  double w_rad_per_s = 1.0;
  double zeta = 0.0;
  double force = 0.0;              // F
  double forcing_rad_per_s = 0.0;  // v
  double free_part = 0.0;          // x2(0) less the forced response's
  void operator()(const State& x, State& dx, double t) const {
    dx[0] = x[2];
    dx[1] = x[3];
    dx[2] = -x[0];
    dx[3] =
        -w_rad_per_s * w_rad_per_s * x[1] - 2.0 * zeta * w_rad_per_s * x[3] + force * std::cos(forcing_rad_per_s * t);
  }
  // x2 exactly (zeta = 0 when forced): the forced response, and the free part released at rest.
  double x2(double t) const {
    const double r = std::sqrt(1.0 - zeta * zeta), wd = w_rad_per_s * r;
    const double free =
        free_part * std::exp(-zeta * w_rad_per_s * t) * (std::cos(wd * t) + zeta / r * std::sin(wd * t));
    return free + force * std::cos(forcing_rad_per_s * t) /
                      (w_rad_per_s * w_rad_per_s - forcing_rad_per_s * forcing_rad_per_s);
  }
};

// Positions (x1, x2), then their velocities: the Hermite output's pairs.
struct TwoOscillatorLayout {
  static constexpr int kDof = 2;
  static constexpr int kSpinSize = 0;
  static constexpr int kSize = 4;
  static constexpr int kModal = kSize;
  using State = Eigen::Vector4d;
};

using Switch = core::DenseStiffnessSwitch<TwoOscillatorLayout>;
using Dop853 = core::DenseDop853<TwoOscillatorLayout>;

constexpr double kRtol = 1e-8, kAtol = 1e-10;
constexpr double kEnd_s = 20.0;
constexpr long kMaxSteps = 10000000;

struct Outcome {
  long steps = 0;
  long switches = 0;
  long jacobians = 0;      // RODASP's, on the switch's probes and steps
  double max_error = 0.0;  // against x1 = cos t, x2 = 0, over the steps' ends
  core::Integrator last_scheme = core::Integrator::kDop853;
};

template <class Integ>
Outcome run(const TwoOscillators& sys) {
  Integ integ(kAtol, kRtol, 1e-14, kMaxSteps);
  core::RunStats stats;
  TwoOscillators s = sys;
  integ.initialize(s, State(1.0, sys.x2(0.0), 0.0, 0.0), 0.0, 1e-4, stats);
  Outcome o;
  while (integ.t_new() < kEnd_s) {
    integ.do_step(s, stats);
    const double t = integ.t_new();
    const State& x = integ.x_new();
    o.max_error = std::max({o.max_error, std::abs(x[0] - std::cos(t)), std::abs(x[1] - sys.x2(t))});
    if constexpr (std::is_same_v<Integ, Switch>) o.last_scheme = integ.scheme_now();
  }
  o.steps = stats.steps;
  o.switches = stats.integrator_switches;
  o.jacobians = stats.jacobian_evals;
  return o;
}

// The error over 20 s at rtol 1e-8, within 100 times rtol: each scheme keeps
// it below 4e-8 over these ~3 periods.
constexpr double kGlobalError = 1e-6;

// With the fast mode at 1e4 rad/s (damped lightly, as a shaft's), dop853's
// steps are its stability's, 6e-4 s; RODASP's are the slow motion's. The
// switch takes RODASP for good and as few steps as that.
TEST(StiffnessSwitch, AFastModeAtRestMovesTheFlightToRodasp) {
  TwoOscillators sys;
  sys.w_rad_per_s = 1e4;
  sys.zeta = 0.01;
  sys.free_part = 1e-14;
  const Outcome explicit_only = run<Dop853>(sys);
  const Outcome hybrid = run<Switch>(sys);
  EXPECT_EQ(hybrid.switches, 1);
  EXPECT_EQ(hybrid.last_scheme, core::Integrator::kRosenbrock4);
  // dop853 alone: 20 s at h w <= 6 is at least 3.3e4 steps.
  EXPECT_GT(explicit_only.steps, 20.0 * 1e4 / 6.0);
  EXPECT_LT(hybrid.steps * 10, explicit_only.steps) << hybrid.steps << " against " << explicit_only.steps;
  EXPECT_LT(hybrid.max_error, kGlobalError);
  EXPECT_LT(explicit_only.max_error, kGlobalError);
}

// A second mode of 10 rad/s, rung, is within dop853's accuracy steps: no
// probe, no switch, and the steps are dop853's own, to the bit.
TEST(StiffnessSwitch, WithoutAStiffModeItIsDop853StepForStep) {
  TwoOscillators sys;
  sys.w_rad_per_s = 10.0;
  sys.free_part = 1e-3;  // rung, so that the mode is in every step's error
  const Outcome explicit_only = run<Dop853>(sys);
  const Outcome hybrid = run<Switch>(sys);
  EXPECT_EQ(hybrid.switches, 0);
  EXPECT_EQ(hybrid.jacobians, 0);
  EXPECT_EQ(hybrid.steps, explicit_only.steps);
  EXPECT_EQ(hybrid.max_error, explicit_only.max_error);
  EXPECT_LT(hybrid.max_error, kGlobalError);
}

// The fast mode forced at 150 rad/s: dop853 stands at its stability, and
// RODASP's order 4 resolves the forcing in steps hardly longer (w h ~ 5):
// each probe (15 RODASP steps on the side) loses, and the flight is
// dop853's to the bit. Switched there and back, dop853 had found the fast
// mode rung by RODASP's errors and took 2.4 times its own steps (the same
// forcing at 100 rad/s, where RODASP now wins: 4 694 steps against 51 298).
TEST(StiffnessSwitch, RodaspNoFasterThanDop853LeavesTheFlightAlone) {
  TwoOscillators sys;
  sys.w_rad_per_s = 1e4;
  sys.force = 0.1;
  sys.forcing_rad_per_s = 150.0;
  const Outcome explicit_only = run<Dop853>(sys);
  const Outcome hybrid = run<Switch>(sys);
  EXPECT_GT(hybrid.jacobians, 0) << "no probe";
  EXPECT_EQ(hybrid.jacobians % Switch::kWindowSteps, 0) << "probes only";
  EXPECT_EQ(hybrid.switches, 0);
  EXPECT_EQ(hybrid.steps, explicit_only.steps);
  EXPECT_EQ(hybrid.max_error, explicit_only.max_error);
  EXPECT_LT(hybrid.max_error, kGlobalError);
}

}  // namespace
}  // namespace rotor_rub
