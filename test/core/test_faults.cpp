// Faults as live changes (faults.hpp): each fault's change in closed form,
// its range checks, and a blade loss and a loosened support applied to a
// running simulation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/faults.hpp"
#include "rotor_rub_sim/core/fe_rotor.hpp"
#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/rotor_reduction.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
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
  const core::Scene scene;
  const core::ModelParameters& p = scene.model;
  const double me = p.rotor_mass_kg * p.eccentricity_m;
  auto after = [&](double lost, double phase) {
    core::Fault f{core::FaultKind::kBladeLoss, lost, phase, 0.0};
    const auto steps = core::fault_steps(f, scene, 1000.0);
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
  const core::Scene scene;
  const core::ModelParameters& p = scene.model;
  const auto steps = core::fault_steps({core::FaultKind::kThermalClosure, 1e-4, 0.0, 0.01}, scene, 1000.0);
  ASSERT_EQ(steps.size(), 10u);
  for (std::size_t k = 0; k < steps.size(); ++k) {
    EXPECT_NEAR(steps[k].offset_s, 1e-3 * static_cast<double>(k + 1), 1e-15);
    EXPECT_NEAR(value(steps[k], "clearance_m"), p.clearance_m - 1e-5 * static_cast<double>(k + 1), 1e-15);
    EXPECT_TRUE(steps[k].stop_at_rotor);  // a closure stops where it meets the rotor
  }
  const auto wear = core::fault_steps({core::FaultKind::kSealWear, 1e-4, 0.0, 0.0}, scene, 1000.0);
  ASSERT_EQ(wear.size(), 1u);
  EXPECT_EQ(value(wear[0], "clearance_m"), p.clearance_m + 1e-4);
  EXPECT_FALSE(wear[0].stop_at_rotor);
  const auto loose = core::fault_steps({core::FaultKind::kSupportLoosening, 0.75, 0.0, 0.0}, scene, 1000.0);
  EXPECT_EQ(value(loose[0], "stator_stiffness_N_per_m"), p.stator_stiffness_N_per_m * 0.25);
  const auto friction = core::fault_steps({core::FaultKind::kFrictionChange, 0.4, 0.0, 0.0}, scene, 1000.0);
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
  for (const auto& step : core::fault_steps({core::FaultKind::kBladeLoss, 0.5 * me, M_PI, 0.0}, sim.scene(), 1e3)) {
    sim.change_parameters(step.changes);
  }
  EXPECT_NEAR(sim.scene().model.eccentricity_m, 1.5 * s.model.eccentricity_m, 1e-18);
  for (const auto& step : core::fault_steps({core::FaultKind::kSupportLoosening, 0.5, 0.0, 0.0}, sim.scene(), 1e3)) {
    sim.change_parameters(step.changes);
  }
  EXPECT_EQ(sim.scene().model.stator_stiffness_N_per_m, 0.5 * s.model.stator_stiffness_N_per_m);
  ASSERT_TRUE(sim.advance_to(0.2, out));
}

// A blade loss on a flexible rotor, applied to the file's unbalances: the
// seal-rub rotor (anisotropic bearings, a cross-coupled seal) at a constant
// 300 rad/s, scene unbalance_phase_rad 0.3 (which turns the file's
// unbalances, not the keyphasor's notch), loses 2e-4 kg m from disk 9 at
// 1 rad on the shaft. Before the loss the station holds the file's
// unbalance response, after it the response of the file's unbalances plus
// 2e-4 kg m at 1 + pi, both from the full FE model (unbalance_response).
// Bound: the reduction's judged error plus 1e-4 of the largest displacement
// for the transient left after 10 s and the integration's error (as
// AutoModesHoldTheUnbalanceResponseInEveryMethod); the loss moves the
// response by several times that.
TEST(Faults, BladeLossOnTheSealRotorSettlesOnItsClosedForm) {
  const std::string file = test::source_path("config/rotors/seal_rub.yaml");
  const core::FeRotor rotor = core::load_rotor_file(file);
  const core::RotorMatrices full = core::assemble(rotor);
  constexpr double kW_rad_per_s = 300.0, kBeta_rad = 0.3, kLost_kg_m = 2e-4, kPhase_rad = 1.0;
  constexpr double kSettled_s = 10.0;  // the 241 rad/s mode (zeta 0.0045) decays by 1e-4 in 8.5 s
  std::vector<core::RotorUnbalance> before = rotor.unbalances;
  for (auto& u : before) u.phase_rad += kBeta_rad;
  std::vector<core::RotorUnbalance> after = before;
  after.push_back({9, kLost_kg_m, kPhase_rad + M_PI});
  struct Response {
    Eigen::VectorXcd q;
    double largest_m = 0.0;
  };
  auto response = [&](const std::vector<core::RotorUnbalance>& u) {
    Response r{core::unbalance_response(full, u, kW_rad_per_s)};
    for (int node = 0; node < rotor.nodes(); ++node) {
      r.largest_m = std::max({r.largest_m, std::abs(r.q(core::dof_index(node, core::kDofX))),
                              std::abs(r.q(core::dof_index(node, core::kDofY)))});
    }
    return r;
  };
  const Response old_response = response(before), new_response = response(after);
  auto at = [](const Response& r, int node, double t_s) {
    const std::complex<double> turn = std::exp(std::complex<double>(0.0, kW_rad_per_s * t_s));
    return core::Vec2((r.q(core::dof_index(node, core::kDofX)) * turn).real(),
                      (r.q(core::dof_index(node, core::kDofY)) * turn).real());
  };
  for (const test::Solver& solver : {test::Solver{core::Method::kSwitching, core::Integrator::kDop853},
                                     test::Solver{core::Method::kIteration, core::Integrator::kDop853},
                                     test::Solver{core::Method::kPenalty, core::Integrator::kDopri5}}) {
    SCOPED_TRACE(solver.name());
    core::Scene s;
    s.rotor.file = file;
    s.rotor.planar_modes = 0;  // auto, 1e-3
    s.solver.method = solver.method;
    s.solver.integrator = solver.integrator;
    s.solver.rtol = 1e-7;
    s.solver.atol = 1e-11;
    s.model.stator_model = core::StatorModel::kRigid;
    s.model.clearance_m = 1e-2;  // never reached
    s.model.unbalance_phase_rad = kBeta_rad;
    s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = kW_rad_per_s;
    s.speed.acceleration_rad_per_s2 = 0.0;
    s.end_time_s = 2.0 * kSettled_s;
    s.output_rate_hz = 10.0;
    core::Simulation sim(s);
    const double bound = sim.reduction().truncation.response_error + 1e-4;
    test::Collect out;
    ASSERT_TRUE(sim.advance_to(kSettled_s, out)) << sim.failure()->message;
    const core::Sample loss = out.samples.back();
    const int station = rotor.rub_station_node, probe = rotor.probe_nodes.front();
    EXPECT_LT((loss.kin.rotor_pos - at(old_response, station, loss.t_s)).norm() / old_response.largest_m, bound);
    EXPECT_LT((loss.probe_displacement_m - at(old_response, probe, loss.t_s)).norm() / old_response.largest_m, bound);
    EXPECT_GT(
        (at(new_response, station, loss.t_s) - at(old_response, station, loss.t_s)).norm() / new_response.largest_m,
        5.0 * bound);
    const auto steps =
        core::fault_steps({core::FaultKind::kBladeLoss, kLost_kg_m, kPhase_rad, 0.0, 9}, sim.scene(), 1e2);
    ASSERT_EQ(steps.size(), 1u);
    EXPECT_TRUE(steps[0].changes.empty());
    sim.change_parameters(steps[0].changes, steps[0].unbalances_added);
    ASSERT_TRUE(sim.advance_to(s.end_time_s, out)) << sim.failure()->message;
    ASSERT_TRUE(out.events.empty());
    const core::Sample& end = out.samples.back();
    EXPECT_LT((end.kin.rotor_pos - at(new_response, station, end.t_s)).norm() / new_response.largest_m, bound);
    EXPECT_LT((end.probe_displacement_m - at(new_response, probe, end.t_s)).norm() / new_response.largest_m, bound);
  }
}

// A blade loss takes effect at its instant: the state a method restarts from
// there is the old rotor's, bit for bit the state a change of nothing at the
// same instant restarts from. An implicit integrator takes its step again
// to end there (DenseRodasp::end_step_at) under the old unbalances; under
// the new ones its stages would carry the loss back to the step's start.
// Every solver on the seal-rub rotor, at a time no step or sample ends on.
TEST(Faults, BladeLossActsFromItsInstant) {
  constexpr double kChange_s = 0.0123456;
  for (const test::Solver& solver : test::all_solvers()) {
    SCOPED_TRACE(solver.name());
    core::Scene s;
    s.rotor.file = test::source_path("config/rotors/seal_rub.yaml");
    s.rotor.planar_modes = 8;
    s.solver.method = solver.method;
    s.solver.integrator = solver.integrator;
    s.model.stator_model = core::StatorModel::kRigid;
    s.model.clearance_m = 1e-2;  // never reached
    s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = 300.0;
    s.speed.acceleration_rad_per_s2 = 0.0;
    s.end_time_s = 0.05;
    auto distance_after = [&](const std::vector<core::RotorUnbalance>& lost) {
      core::Simulation sim(s);
      test::Collect out;
      EXPECT_TRUE(sim.advance_to(kChange_s, out));
      sim.change_parameters({}, lost);
      return sim.rotor_stator_distance_m();
    };
    EXPECT_EQ(distance_after({{9, 2e-4, 1.0}}), distance_after({}));
  }
}

// A blade is lost from a disk: at a node without one (the message's default
// node 0, a bearing) it is refused on receipt, naming the disks' nodes; a
// Jeffcott has node 0 only; a Jeffcott's scene takes no unbalance at a node.
TEST(Faults, BladeLossNodeIsADisksNode) {
  core::Scene s;
  s.rotor.file = test::source_path("config/rotors/seal_rub.yaml");
  s.rotor.planar_modes = 4;
  auto refusal = [](const core::Fault& f, const core::Scene& scene) -> std::string {
    try {
      core::fault_steps(f, scene, 1e3);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_NE(
      refusal({core::FaultKind::kBladeLoss, 1e-4, 0.0, 0.0, 0}, s)
          .find("fault node 0 is out of range; accepted for '" + s.rotor.file + "': a node with a disk (3, 6, 9)"),
      std::string::npos);
  EXPECT_EQ(refusal({core::FaultKind::kBladeLoss, 1e-4, 0.0, 0.0, 3}, s), "accepted");
  const core::Scene jeffcott;
  EXPECT_NE(refusal({core::FaultKind::kBladeLoss, 1e-4, 0.0, 0.0, 2}, jeffcott)
                .find("fault node 2 is out of range; accepted: 0 (the Jeffcott rotor's one disk)"),
            std::string::npos);
  core::Simulation sim(jeffcott);
  EXPECT_THROW(sim.change_parameters({}, {{0, 1e-4, 0.0}}), core::SceneError);
}
