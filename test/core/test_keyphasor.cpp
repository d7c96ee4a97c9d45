// The keyphasor (SimulationObserver::on_keyphasor): once per revolution, at
// the instant the spin angle passes 2 pi k, the state from the dense output.
// Checked against the drive's closed form (mark times) and the Jeffcott
// rotor's steady unbalance response (the Poincare point of a period-1 orbit).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "test_support.hpp"

using namespace rotor_rub;

namespace {

struct Marks : core::SimulationObserver {
  std::vector<core::Sample> marks;
  bool wants_keyphasor() const override { return true; }
  void on_keyphasor(const core::Sample& s) override { marks.push_back(s); }
};

// The paper rotor with a clearance it never reaches: free flight.
core::Scene free_scene(double speed_rad_per_s, double end_time_s) {
  core::Scene s = test::paper_scene();
  s.model.clearance_m = 0.05;
  s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = speed_rad_per_s;
  s.end_time_s = end_time_s;
  s.solver.rtol = 1e-10;
  s.solver.atol = 1e-13;
  return s;
}

// Mark times are the drive's: exact up to the root's rounding.
constexpr double kMarkTimeTol_s = 1e-12;
// rtol 1e-10 over 30 s of forced response of a 1 mm orbit: the global error
// stays below 1e-9 m (checked against rtol 1e-11); the transient has decayed
// by exp(-zeta w_n 25 s) = 1e-17.
constexpr double kSteadyOrbitTol_m = 1e-9;

}  // namespace

TEST(Keyphasor, MarksAtConstantSpeedAreEvery2PiOverOmega) {
  const double w = 100.0;
  Marks m;
  core::run_scene(free_scene(w, 1.0), m);
  ASSERT_EQ(m.marks.size(), static_cast<std::size_t>(std::floor(w * 1.0 / (2 * M_PI))));
  for (std::size_t k = 0; k < m.marks.size(); ++k) {
    EXPECT_NEAR(m.marks[k].t_s, 2 * M_PI * double(k + 1) / w, kMarkTimeTol_s) << k;
    EXPECT_NEAR(m.marks[k].drive.angle_rad, 2 * M_PI * double(k + 1), 1e-9) << k;
  }
}

TEST(Keyphasor, MarksOnARampFollowTheQuadraticAngle) {
  core::Scene s = test::paper_scene();  // 0 -> 280 rad/s at 70 rad/s^2, then held
  s.end_time_s = 4.5;
  Marks m;
  core::run_scene(s, m);
  ASSERT_GT(m.marks.size(), 80u);
  for (std::size_t k = 0; k < m.marks.size(); ++k) {
    const double angle = 2 * M_PI * double(k + 1);
    // phi = 0.5 A t^2 up to 4 s (phi = 560 rad), then phi = 560 + 280 (t - 4).
    const double t = angle <= 560.0 ? std::sqrt(2.0 * angle / 70.0) : 4.0 + (angle - 560.0) / 280.0;
    EXPECT_NEAR(m.marks[k].t_s, t, kMarkTimeTol_s) << k;
  }
}

// At a keyphasor the steady unbalance response z = m e w^2 / (k - m w^2 + i c w)
// (the mass centre offset e (cos phi, sin phi), phi = 2 pi k), plus the static
// sag -m g / k under gravity; below and above the critical speed.
TEST(Keyphasor, PoincarePointOfTheSteadyUnbalanceResponse) {
  for (const double w : {50.0, 100.0, 250.0}) {
    for (const double g : {0.0, 9.81}) {
      core::Scene s = free_scene(w, 30.0);
      s.model.gravity_m_per_s2 = g;
      Marks m;
      core::run_scene(s, m);
      const auto& p = s.model;
      const std::complex<double> z =
          p.rotor_mass_kg * p.eccentricity_m * w * w /
              std::complex<double>(p.rotor_stiffness_N_per_m - p.rotor_mass_kg * w * w, p.rotor_damping_N_s_per_m * w) +
          std::complex<double>(0.0, -p.rotor_mass_kg * g / p.rotor_stiffness_N_per_m);
      int checked = 0;
      for (const auto& mark : m.marks) {
        if (mark.t_s < 25.0) continue;
        EXPECT_NEAR(mark.kin.rotor_pos.x(), z.real(), kSteadyOrbitTol_m) << "w " << w << " g " << g;
        EXPECT_NEAR(mark.kin.rotor_pos.y(), z.imag(), kSteadyOrbitTol_m) << "w " << w << " g " << g;
        ++checked;
      }
      EXPECT_GT(checked, 30) << w;
    }
  }
}

// The marks come from the dense output: the output rate does not move them
// (the paper scene through its first contacts, every method).
TEST(Keyphasor, MarksDoNotDependOnTheOutputRate) {
  for (const auto method : {core::Method::kSwitching, core::Method::kIteration, core::Method::kPenalty}) {
    std::vector<std::vector<core::Sample>> runs;
    for (const double rate : {100.0, 1000.0, 20000.0}) {
      core::Scene s = test::paper_scene();
      s.end_time_s = 1.6;
      s.output_rate_hz = rate;
      s.solver.method = method;
      Marks m;
      core::run_scene(s, m);
      runs.push_back(m.marks);
    }
    bool contact = false;
    for (const auto& mark : runs[0]) contact = contact || mark.in_contact;
    EXPECT_TRUE(contact) << core::to_string(method);
    for (std::size_t r = 1; r < runs.size(); ++r) {
      ASSERT_EQ(runs[r].size(), runs[0].size());
      for (std::size_t k = 0; k < runs[0].size(); ++k) {
        EXPECT_EQ(runs[r][k].t_s, runs[0][k].t_s);
        EXPECT_EQ(runs[r][k].kin.rotor_pos, runs[0][k].kin.rotor_pos) << core::to_string(method) << " mark " << k;
        EXPECT_EQ(runs[r][k].normal_force_N, runs[0][k].normal_force_N);
      }
    }
  }
}

// A speed command issued exactly at a mark puts a segment boundary on it:
// no mark is lost or doubled (every multiple of 2 pi once, in order).
TEST(Keyphasor, AMarkOnASegmentBoundaryIsKeptOnce) {
  const double w = 100.0;
  core::Scene s = free_scene(w, 3.0);
  core::Simulation sim(s);
  Marks m;
  sim.advance_to(2 * M_PI * 5 / w, m);  // the 5th mark's time
  sim.command_speed(200.0, 50.0);
  sim.advance_to(s.end_time_s, m);
  ASSERT_GT(m.marks.size(), 50u);
  for (std::size_t k = 0; k < m.marks.size(); ++k) {
    EXPECT_NEAR(m.marks[k].drive.angle_rad, 2 * M_PI * double(k + 1), 1e-9) << k;
  }
}
