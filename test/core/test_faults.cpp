// Faults as live changes (faults.hpp): each fault's change in closed form,
// its range checks, and a blade loss and a loosened support applied to a
// running simulation.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <string>

#include "rotor_rub_sim/core/faults.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

double value(const core::FaultStep& s, const std::string& key) { return std::stod(s.changes.at(key)); }

std::string refusal(const core::Fault& f) {
  try {
    core::check_fault(f);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace

// Losing m_b r_b = m e (the whole unbalance) from its own angle leaves none;
// losing it from the opposite side doubles it; a quarter turn away gives the
// vector sum sqrt(2) m e at 135 degrees.
TEST(Faults, BladeLossIsTheVectorSumOfTheUnbalances) {
  core::ModelParameters p;
  const double me = p.rotor_mass_kg * p.eccentricity_m;
  auto after = [&](double lost, double phase) {
    core::Fault f{core::FaultKind::kBladeLoss, lost, phase, 0.0};
    const auto steps = core::fault_steps(f, p, 1000.0);
    EXPECT_EQ(steps.size(), 1u);
    EXPECT_EQ(steps[0].offset_s, 0.0);
    return std::polar(value(steps[0], "eccentricity_m"), value(steps[0], "unbalance_phase_rad"));
  };
  EXPECT_NEAR(std::abs(after(me, 0.0)), 0.0, 1e-18);
  EXPECT_NEAR(std::abs(after(me, M_PI) - std::polar(2.0 * p.eccentricity_m, 0.0)), 0.0, 1e-18);
  // rotor_mass 0.418 kg: m e / m = e exactly up to rounding (1e-19 m).
  EXPECT_NEAR(std::abs(after(me, -M_PI / 2) - std::polar(std::sqrt(2.0) * p.eccentricity_m, M_PI / 4)), 0.0, 1e-18);
}

// A ramp of 0.1 mm over 10 ms at 1 kHz: ten equal steps, the k-th at k ms.
TEST(Faults, ClearanceRampIsAStaircaseAsFineAsTheOutput) {
  core::ModelParameters p;
  const auto steps = core::fault_steps({core::FaultKind::kThermalClosure, 1e-4, 0.0, 0.01}, p, 1000.0);
  ASSERT_EQ(steps.size(), 10u);
  for (std::size_t k = 0; k < steps.size(); ++k) {
    EXPECT_NEAR(steps[k].offset_s, 1e-3 * static_cast<double>(k + 1), 1e-15);
    EXPECT_NEAR(value(steps[k], "clearance_m"), p.clearance_m - 1e-5 * static_cast<double>(k + 1), 1e-15);
    EXPECT_TRUE(steps[k].stop_at_rotor);  // a closure stops where it meets the rotor
  }
  const auto wear = core::fault_steps({core::FaultKind::kSealWear, 1e-4, 0.0, 0.0}, p, 1000.0);
  ASSERT_EQ(wear.size(), 1u);
  EXPECT_EQ(value(wear[0], "clearance_m"), p.clearance_m + 1e-4);
  EXPECT_FALSE(wear[0].stop_at_rotor);
  const auto loose = core::fault_steps({core::FaultKind::kSupportLoosening, 0.75, 0.0, 0.0}, p, 1000.0);
  EXPECT_EQ(value(loose[0], "stator_stiffness_N_per_m"), p.stator_stiffness_N_per_m * 0.25);
  const auto friction = core::fault_steps({core::FaultKind::kFrictionChange, 0.4, 0.0, 0.0}, p, 1000.0);
  EXPECT_EQ(value(friction[0], "friction_coefficient"), 0.4);
}

TEST(Faults, OutOfRangeIsRefusedNamingTheField) {
  EXPECT_NE(refusal({core::FaultKind::kBladeLoss, -1e-4, 0.0, 0.0}).find("magnitude -0.0001 is out of range"),
            std::string::npos);
  EXPECT_NE(refusal({core::FaultKind::kBladeLoss, NAN, 0.0, 0.0}).find("magnitude NaN is not a finite number"),
            std::string::npos);
  EXPECT_NE(refusal({core::FaultKind::kSupportLoosening, 1.0, 0.0, 0.0}).find("[0, 1)"), std::string::npos);
  EXPECT_NE(refusal({core::FaultKind::kFrictionChange, 0.2, 0.0, 1.0}).find("duration"), std::string::npos);
  EXPECT_EQ(refusal({core::FaultKind::kSealWear, 1e-4, 0.0, 2.0}), "accepted");
}

// A blade loss applied to a running simulation: the unbalance response
// after it is the closed form's with the vector sum (test_live_parameters
// covers the response itself; here, that the fault's change is accepted and
// lands in the scene).
TEST(Faults, AppliedToARunningSimulation) {
  core::Scene s = test::paper_scene();
  s.end_time_s = 0.2;
  core::Simulation sim(s);
  test::Collect out;
  ASSERT_TRUE(sim.advance_to(0.1, out));
  const double me = s.model.rotor_mass_kg * s.model.eccentricity_m;
  for (const auto& step :
       core::fault_steps({core::FaultKind::kBladeLoss, 0.5 * me, M_PI, 0.0}, sim.scene().model, 1e3)) {
    sim.change_parameters(step.changes);
  }
  EXPECT_NEAR(sim.scene().model.eccentricity_m, 1.5 * s.model.eccentricity_m, 1e-18);
  for (const auto& step :
       core::fault_steps({core::FaultKind::kSupportLoosening, 0.5, 0.0, 0.0}, sim.scene().model, 1e3)) {
    sim.change_parameters(step.changes);
  }
  EXPECT_EQ(sim.scene().model.stator_stiffness_N_per_m, 0.5 * s.model.stator_stiffness_N_per_m);
  ASSERT_TRUE(sim.advance_to(0.2, out));
}
