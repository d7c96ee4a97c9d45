// Large models. A rotor of more than 64 nodes at its full FE model, beyond the
// 128 planar modes a state held before (kMaxPlanarModes, state_layout.hpp):
// fine_damped_seal.yaml (73 nodes, 146 planar modes; with every mode kept the
// reduction is exact) started from rest at a constant speed follows the full
// FE model's transient in closed form, on rosenbrock4 (an explicit scheme's
// step would be set by the model's highest mode). The other methods' free
// flights at this size: test_allocations. And switching on rosenbrock4 on
// ROSS's rig at 48 planar modes, through its first contacts; and the
// stiffness switch (auto) there at 20.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdio>
#include <unsupported/Eigen/MatrixFunctions>

#include "rotor_rub_sim/core/fe_rotor.hpp"
#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/rotor_reduction.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

// The run's error against the closed form, relative to the largest
// displacement over the window: the integration's at rtol 1e-6 (measured
// 1.2e-8; the closed form's own rounding is below 1e-12).
constexpr double kIntegrationTolerance = 1e-6;
// The samples fall at k / rate_hz, up to the rounding of that product.
constexpr double kSampleTimeTolerance_s = 1e-12;

// The full FE model's response from rest to its unbalances at a constant
// speed w (spin angle w t): with z = [q; q' / s], z' = A z + [0; M^-1 Re(F
// e^{iwt}) / s], so z(t) = z_p(t) + e^{A t} (z(0) - z_p(0)), z_p the
// unbalance response and z(0) = 0. Read at t = k dt, k = 0, 1, ... in turn.
class FullModelTransient {
 public:
  FullModelTransient(const core::FeRotor& rotor, double w_rad_per_s, double dt_s) : w_(w_rad_per_s), dt_(dt_s) {
    const core::RotorMatrices m = core::assemble(rotor);
    const long n = m.M.rows();
    steady_ = core::unbalance_response(m, rotor.unbalances, w_);
    const Eigen::LLT<Eigen::MatrixXd> mass(m.M);
    const Eigen::MatrixXd stiffness = mass.solve(m.K);
    // The velocities divided by the highest frequency's bound, so that both
    // halves of z are of one scale: unscaled, e^{A dt}'s rounding put 1e-7 of
    // the largest displacement into the positions (the runs agreed to 1e-12
    // with the scaled one at rtol 1e-10).
    const double scale = std::sqrt(stiffness.cwiseAbs().rowwise().sum().maxCoeff());
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(2 * n, 2 * n);
    a.topRightCorner(n, n).setIdentity();
    a.topRightCorner(n, n) *= scale;
    a.bottomLeftCorner(n, n) = -stiffness / scale;
    a.bottomRightCorner(n, n) = -mass.solve(m.C + w_ * m.G);
    step_ = (a * dt_).exp();
    homogeneous_.resize(2 * n);
    homogeneous_ << -steady_.real(), -(std::complex<double>(0.0, w_) * steady_).real() / scale;
  }

  // q at the next instant k dt (the first call: t = 0).
  Eigen::VectorXd next(double* t_s) {
    *t_s = k_ * dt_;
    const Eigen::VectorXd q =
        (steady_ * std::exp(std::complex<double>(0.0, w_ * *t_s))).real() + homogeneous_.head(steady_.size());
    homogeneous_ = step_ * homogeneous_;
    ++k_;
    return q;
  }

 private:
  double w_, dt_;
  long k_ = 0;
  Eigen::VectorXcd steady_;
  Eigen::MatrixXd step_;
  Eigen::VectorXd homogeneous_;
};

}  // namespace

TEST(LargeRotor, AFullModelOfMoreThan64NodesFollowsTheClosedFormTransient) {
  const std::string file = test::source_path("test/data/rotors/fine_damped_seal.yaml");
  const core::FeRotor rotor = core::load_rotor_file(file);
  const int full = core::max_planar_modes(rotor);
  ASSERT_EQ(full, 146);
  // 0.6 of a revolution: the model's high modes, which the start from rest
  // rings, hold rosenbrock4 to steps of about 1.5 us at this tolerance.
  const double w = 300.0, rate_hz = 20000.0, end_s = 0.002;
  core::Scene s;
  s.rotor.file = file;
  s.rotor.planar_modes = full;
  s.solver.method = core::Method::kSwitching;
  s.solver.integrator = core::Integrator::kRosenbrock4;
  s.model.stator_model = core::StatorModel::kRigid;
  s.model.clearance_m = 1e-3;  // never reached
  s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = w;
  s.speed.acceleration_rad_per_s2 = 0.0;
  s.end_time_s = end_s;
  s.output_rate_hz = rate_hz;
  s.solver.rtol = 1e-6;
  s.solver.atol = 1e-10;
  const test::Run r = test::run(s);
  ASSERT_FALSE(r.result.failure) << r.result.failure->message;
  ASSERT_TRUE(r.out.events.empty());
  ASSERT_GE(r.out.samples.size(), 40u);
  FullModelTransient exact(rotor, w, 1.0 / rate_hz);
  double largest_m = 0.0, station_err_m = 0.0, probe_err_m = 0.0;
  for (const core::Sample& sample : r.out.samples) {
    double t_s = 0.0;
    const Eigen::VectorXd q = exact.next(&t_s);
    ASSERT_NEAR(sample.t_s, t_s, kSampleTimeTolerance_s);
    auto at = [&](int node) {
      return core::Vec2(q(core::dof_index(node, core::kDofX)), q(core::dof_index(node, core::kDofY)));
    };
    for (int node = 0; node < rotor.nodes(); ++node) largest_m = std::max(largest_m, at(node).norm());
    station_err_m = std::max(station_err_m, (sample.kin.rotor_pos - at(rotor.rub_station_node)).norm());
    probe_err_m = std::max(probe_err_m, (sample.probe_displacement_m - at(rotor.probe_nodes.front())).norm());
  }
  std::printf("%zu samples, largest %.3g m, station %.3g, probe %.3g of it\n", r.out.samples.size(), largest_m,
              station_err_m / largest_m, probe_err_m / largest_m);
  EXPECT_LT(station_err_m, kIntegrationTolerance * largest_m);
  EXPECT_LT(probe_err_m, kIntegrationTolerance * largest_m);
}

// Switching on rosenbrock4 flies on RODASP and holds contact on dop853. With
// the flight's long step carried into contact, dop853's first contact steps on
// ROSS's rig from 40 planar modes overflowed (at 48 the run diverged at the
// first touchdown, 0.0278 s): contact after such a flight now begins with the
// first trial step, and a non-finite trial is rejected (step_ends.hpp), so
// that a long initial_step_s survives too. Through the first touchdown, its lift-off and the
// next touchdown the run agrees with the iteration method on rosenbrock4,
// whose contact is another scheme's.
TEST(LargeRotor, SwitchingOnRosenbrock4TouchesDownAfterALongFlight) {
  // The two methods' events and stations at rtol 1e-6 (measured: 2e-6 s and
  // 1.2e-10 m, against a clearance of 4e-5 m).
  constexpr double kEventTolerance_s = 1e-5, kStationTolerance_m = 1e-8;
  auto run = [](core::Method method, double initial_step_s) {
    core::Scene s = core::load_scene(test::source_path("config/ross_rig_rub.yaml"));
    s.rotor.planar_modes = 48;
    s.solver.method = method;
    s.solver.integrator = core::Integrator::kRosenbrock4;
    s.solver.initial_step_s = initial_step_s;
    s.end_time_s = 0.03;
    return test::run(s);
  };
  const test::Run iteration = run(core::Method::kIteration, 1e-5);
  ASSERT_FALSE(iteration.result.failure) << iteration.result.failure->message;
  // The scene's first step (1e-5 s), and a hundred times it: dop853's first
  // contact step then overflows and is cut.
  for (const double initial_step_s : {1e-5, 1e-3}) {
    SCOPED_TRACE(initial_step_s);
    const test::Run switching = run(core::Method::kSwitching, initial_step_s);
    ASSERT_FALSE(switching.result.failure) << switching.result.failure->message;
    ASSERT_GE(switching.out.events.size(), 3u);  // a touchdown, its lift-off, the next touchdown
    ASSERT_EQ(switching.out.events.size(), iteration.out.events.size());
    for (std::size_t i = 0; i < switching.out.events.size(); ++i) {
      EXPECT_EQ(switching.out.events[i].kind, iteration.out.events[i].kind) << i;
      EXPECT_NEAR(switching.out.events[i].t_s, iteration.out.events[i].t_s, kEventTolerance_s) << i;
    }
    ASSERT_EQ(switching.out.samples.size(), iteration.out.samples.size());
    for (std::size_t i = 0; i < switching.out.samples.size(); ++i) {
      EXPECT_LT((switching.out.samples[i].kin.rotor_pos - iteration.out.samples[i].kin.rotor_pos).norm(),
                kStationTolerance_m)
          << switching.out.samples[i].t_s;
    }
  }
}

// auto on ROSS's rig at 20 planar modes is dop853_rosenbrock4 for both rigid
// methods: the bearings' stiff modes hold dop853's free steps to its
// stability, so free flight moves to RODASP (dense_stiffness_switch.hpp), in
// far fewer steps, and the run agrees with dop853's through the first
// contacts (sustained from 0.035 s to 0.048 s) at the test above's
// tolerances.
TEST(LargeRotor, TheStiffnessSwitchTakesRossRigsFlightsToRodaspAndAgreesWithDop853) {
  constexpr double kEventTolerance_s = 1e-5, kStationTolerance_m = 1e-8;
  for (const core::Method method : {core::Method::kSwitching, core::Method::kIteration}) {
    SCOPED_TRACE(core::to_string(method));
    core::Scene s = core::load_scene(test::source_path("config/ross_rig_rub.yaml"));
    s.rotor.planar_modes = 20;
    s.solver.method = method;
    s.end_time_s = 0.06;
    ASSERT_EQ(core::effective_integrator(s), core::Integrator::kDop853Rosenbrock4);
    const test::Run hybrid = test::run(s);
    s.solver.integrator = core::Integrator::kDop853;
    const test::Run dop853 = test::run(s);
    ASSERT_FALSE(hybrid.result.failure) << hybrid.result.failure->message;
    ASSERT_FALSE(dop853.result.failure) << dop853.result.failure->message;
    EXPECT_GE(hybrid.result.stats.integrator_switches, 1);
    EXPECT_LT(2 * hybrid.result.stats.steps, dop853.result.stats.steps)
        << hybrid.result.stats.steps << " against " << dop853.result.stats.steps;
    ASSERT_GE(hybrid.out.events.size(), 2u);
    ASSERT_EQ(hybrid.out.events.size(), dop853.out.events.size());
    for (std::size_t i = 0; i < hybrid.out.events.size(); ++i) {
      const core::ContactEvent &a = hybrid.out.events[i], &b = dop853.out.events[i];
      EXPECT_EQ(a.kind, b.kind) << i;
      // A touch closing at v is as uncertain as the gap over v (as test_golden.cpp holds it): iteration's
      // touchdown right after a graze closes at 4.4e-7 m/s, 1.4e-4 s from dop853's (rosenbrock4's: 9e-5 s).
      const double closing_m_per_s = std::min(std::abs(a.normal_velocity_m_per_s), std::abs(b.normal_velocity_m_per_s));
      const double tolerance_s =
          kEventTolerance_s + (closing_m_per_s > 0.0 ? kStationTolerance_m / closing_m_per_s : 0.0);
      EXPECT_NEAR(a.t_s, b.t_s, tolerance_s) << i;
    }
    ASSERT_EQ(hybrid.out.samples.size(), dop853.out.samples.size());
    double worst_m = 0.0;
    for (std::size_t i = 0; i < hybrid.out.samples.size(); ++i) {
      worst_m = std::max(worst_m, (hybrid.out.samples[i].kin.rotor_pos - dop853.out.samples[i].kin.rotor_pos).norm());
    }
    std::printf("%s: %ld switches, %ld steps against %ld, stations within %.3g m\n", core::to_string(method),
                hybrid.result.stats.integrator_switches, hybrid.result.stats.steps, dop853.result.stats.steps, worst_m);
    EXPECT_LT(worst_m, kStationTolerance_m);
  }
}
