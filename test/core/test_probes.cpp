// The proximity probes (probes.hpp, ProbeParameters): what each probe
// measures against closed forms (runout alone; the steady unbalance orbit
// seen along the probe's axis), seeded noise, and sampling at the probes'
// own rate that leaves the solution untouched.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "rotor_rub_sim/core/probes.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

struct ProbeRecorder : core::SimulationObserver {
  explicit ProbeRecorder(const core::ProbeParameters& p) : pair(p) {}
  bool wants_probes() const override { return true; }
  void on_probe_sample(const core::Sample& s) override {
    states.push_back(s);
    readings.push_back(pair.read(s));
  }
  void on_sample(const core::Sample& s) override { samples.push_back(s); }
  core::ProbePair pair;
  std::vector<core::Sample> states, samples;
  std::vector<core::ProbeReading> readings;
};

// The paper rotor at a constant speed, far from the stator.
core::Scene probe_scene(double w, double end_s) {
  core::Scene s = test::paper_scene();
  s.model.clearance_m = 0.05;
  s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = w;
  s.end_time_s = end_s;
  s.solver.rtol = 1e-10;
  s.solver.atol = 1e-13;
  s.probes.rate_hz = 4000.0;
  return s;
}

// rtol 1e-10 on a 1 mm orbit after the transient (exp(-zeta w_n 25 s) = 1e-17).
constexpr double kOrbitTol_m = 1e-9;

}  // namespace

// With no unbalance the rotor stays centred: each probe sees the runout alone,
// R cos(phi + phase - theta), once per revolution.
TEST(Probes, RunoutAloneIsAOncePerRevolutionCosine) {
  core::Scene s = probe_scene(100.0, 0.5);
  s.model.eccentricity_m = 0.0;
  s.probes.runout_m = 5e-6;
  s.probes.runout_phase_rad = 0.3;
  ProbeRecorder rec(s.probes);
  core::run_scene(s, rec);
  ASSERT_EQ(rec.readings.size(), 2000u);  // k / 4 kHz, k = 1 .. 2000
  for (std::size_t k = 0; k < rec.readings.size(); ++k) {
    const auto& r = rec.readings[k];
    EXPECT_DOUBLE_EQ(r.t_s, double(k + 1) / 4000.0);
    const double phi = 100.0 * r.t_s + 0.3;
    EXPECT_NEAR(r.x_m, 5e-6 * std::cos(phi - s.probes.x_angle_rad), 1e-15);
    EXPECT_NEAR(r.y_m, 5e-6 * std::cos(phi - s.probes.y_angle_rad), 1e-15);
    EXPECT_DOUBLE_EQ(r.x_V, s.probes.sensitivity_V_per_m * r.x_m);  // no noise set
  }
}

// The steady unbalance orbit z = Z e^{i w t}, Z = m e w^2 / (k - m w^2 + i c w),
// seen along an axis at theta: Re(Z e^{i (w t - theta)}); X and Y 90 deg apart.
TEST(Probes, SteadyOrbitAlongEachProbeAxis) {
  const double w = 100.0;
  core::Scene s = probe_scene(w, 30.0);
  s.probes.x_angle_rad = 0.2;  // any mounting
  s.probes.y_angle_rad = 0.2 + M_PI / 2;
  ProbeRecorder rec(s.probes);
  core::run_scene(s, rec);
  const auto& p = s.model;
  const std::complex<double> Z =
      p.rotor_mass_kg * p.eccentricity_m * w * w /
      std::complex<double>(p.rotor_stiffness_N_per_m - p.rotor_mass_kg * w * w, p.rotor_damping_N_s_per_m * w);
  int checked = 0;
  for (const auto& r : rec.readings) {
    if (r.t_s < 25.0) continue;
    const std::complex<double> z = Z * std::polar(1.0, w * r.t_s);
    EXPECT_NEAR(r.x_m, std::real(z * std::polar(1.0, -s.probes.x_angle_rad)), kOrbitTol_m);
    EXPECT_NEAR(r.y_m, std::real(z * std::polar(1.0, -s.probes.y_angle_rad)), kOrbitTol_m);
    ++checked;
  }
  EXPECT_EQ(checked, 20001);  // 25 s to 30 s at 4 kHz, both ends
}

// Noise: the standard deviation asked for, the same for the same seed,
// different for another; it never touches what the probes measure.
TEST(Probes, SeededNoise) {
  auto run = [](long seed) {
    core::Scene s = probe_scene(100.0, 5.0);
    s.probes.noise_V = 0.02;
    s.probes.noise_seed = seed;
    ProbeRecorder rec(s.probes);
    core::run_scene(s, rec);
    return rec.readings;
  };
  const auto a = run(7), b = run(7), c = run(8);
  ASSERT_EQ(a.size(), 20000u);
  double sum2 = 0.0;
  bool differs = false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    const double n = a[k].x_V - 7874.0 * a[k].x_m;
    sum2 += n * n;
    EXPECT_EQ(a[k].x_V, b[k].x_V);
    EXPECT_EQ(a[k].x_m, c[k].x_m);
    differs = differs || a[k].x_V != c[k].x_V;
  }
  // 20000 draws: the sample standard deviation is within 2 % of 0.02 V with
  // probability far above 1 - 1e-6 (its relative spread is 1/sqrt(2 n) = 0.5 %).
  EXPECT_NEAR(std::sqrt(sum2 / double(a.size())), 0.02, 0.02 * 0.02);
  EXPECT_TRUE(differs);
}

// The probes' samples come from the dense output: they do not change the
// solution (the paper scene through its contacts, every method).
TEST(Probes, SamplingLeavesTheSolutionUntouched) {
  for (const auto method : {core::Method::kSwitching, core::Method::kIteration, core::Method::kPenalty}) {
    core::Scene s = test::paper_scene();
    s.end_time_s = 1.5;
    s.solver.method = method;
    const test::Run plain = test::run(s);
    s.probes.rate_hz = 7777.0;  // not a multiple of the output rate
    ProbeRecorder rec(s.probes);
    core::run_scene(s, rec);
    ASSERT_EQ(rec.samples.size(), plain.out.samples.size());
    for (std::size_t k = 0; k < rec.samples.size(); ++k) {
      ASSERT_EQ(rec.samples[k].kin.rotor_pos, plain.out.samples[k].kin.rotor_pos) << core::to_string(method) << k;
    }
    EXPECT_EQ(rec.readings.size(), static_cast<std::size_t>(std::floor(1.5 * 7777.0)));
  }
}
