#include <gtest/gtest.h>

#include <complex>

#include "test_support.hpp"

using namespace rotor_rub;

namespace {

// The transient of the start from rest decays as exp(-zeta w_n t) with
// zeta w_n = b_r / (2 m_r) = 1.56 1/s: after 9 s it is below 1e-6 of the
// initial amplitude; the integrator adds ~rtol. Together well below 1e-5 of
// the steady amplitude.
constexpr double kRelativeTolerance = 1e-5;

}  // namespace

// No contact (clearance 1 m), constant speed: the closed-form Jeffcott
// synchronous response x + i y = m e w^2 / (k - m w^2 + i b w) e^{i w t}.
class FreeResponse : public testing::TestWithParam<std::tuple<test::Solver, core::StatorModel, double>> {};

TEST_P(FreeResponse, MatchesClosedFormAmplitudeAndPhase) {
  const auto [method, stator, w] = GetParam();
  core::Scene s = test::paper_scene();
  s.model.clearance_m = 1.0;
  s.model.stator_model = stator;
  s.speed.initial_speed_rad_per_s = w;
  s.speed.target_speed_rad_per_s = w;
  s.end_time_s = 10.0;
  s.output_rate_hz = 100.0;
  s = test::with_method(s, method, 1e-10, 1e-14);
  const test::Run r = test::run(s);
  ASSERT_FALSE(r.result.failure);
  const auto& p = s.model;
  const std::complex<double> amp =
      p.rotor_mass_kg * p.eccentricity_m * w * w /
      std::complex<double>(p.rotor_stiffness_N_per_m - p.rotor_mass_kg * w * w, p.rotor_damping_N_s_per_m * w);
  double max_err = 0.0;
  for (const auto& smp : r.out.samples) {
    if (smp.t_s < 9.0) continue;
    const std::complex<double> z = amp * std::polar(1.0, w * smp.t_s);
    max_err = std::max(max_err, std::abs(std::complex<double>(smp.kin.rotor_pos.x(), smp.kin.rotor_pos.y()) - z));
  }
  EXPECT_LT(max_err, kRelativeTolerance * std::abs(amp)) << "amplitude " << std::abs(amp);
  EXPECT_EQ(r.result.stats.touchdowns + r.result.stats.grazes, 0);
}

INSTANTIATE_TEST_SUITE_P(AllMethods, FreeResponse,
                         testing::Combine(testing::ValuesIn(test::all_solvers()),
                                          testing::Values(core::StatorModel::kElastic, core::StatorModel::kRigid),
                                          testing::Values(40.0, 77.2, 150.0)));
