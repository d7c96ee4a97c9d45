// The contact methods on a flexible rotor (scene key rotor_file): the rigid
// ones (switching, iteration) on each of their integrators, the penalty
// method on dopri5 and rosenbrock4 (rk4: test_flexible_rk4.cpp). The seam (flexible_rotor_model.hpp,
// docs/rotor_theory.md) against the Jeffcott it must reduce to, the closed-form full annular rub of a multi-DOF rotor,
// the methods against each other, and their promises on the seal-rub example.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <utility>
#include <vector>

#include "methods/event_location.hpp"
#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/invariants.hpp"
#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/rotor_reduction.hpp"
#include "rotor_rub_sim/core/rotor_steady_response.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

core::Scene jeffcott_file_scene(long planar_modes) {
  core::Scene s = test::paper_scene();
  s.rotor.file = test::source_path("test/data/rotors/jeffcott_matrices.yaml");
  s.rotor.planar_modes = planar_modes;
  return s;
}

std::string failure_of(const test::Run& r) { return r.result.failure ? r.result.failure->message : ""; }

double max_position_difference(const test::Run& a, const test::Run& b) {
  EXPECT_EQ(a.out.samples.size(), b.out.samples.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < std::min(a.out.samples.size(), b.out.samples.size()); ++i) {
    worst = std::max(worst, (a.out.samples[i].kin.rotor_pos - b.out.samples[i].kin.rotor_pos).cwiseAbs().maxCoeff());
    worst = std::max(worst, (a.out.samples[i].kin.stator_pos - b.out.samples[i].kin.stator_pos).cwiseAbs().maxCoeff());
  }
  return worst;
}

// JeffcottAsRotorFile.RunsTheJeffcottsMotorRun: the two sum the forces
// and the spin's lever in another order (1e-16 of them; the runs agree to
// 1e-22 m before the first contact), and the 7 to 19 events amplify that
// tenfold at each of several (measured on the run's samples). Switching:
// up to 1.5e-9 m and 2.6e-7 rad/s (dopri5, under gravity; 5e-16 m on
// dop853 there, where leaving out the unbalance's own weight would be off
// by m e g / J = 1.6 rad/s^2). Iteration:
// its force roots converge to their tolerance, not to rounding, so the runs
// part at the first contact (2.5e-12 m in one step) and end up to 3.6e-8 m
// and 2.9e-4 rad/s apart. Penalty: its stiff contact spring amplifies more
// (7.2e-7 m, 1.7e-4 rad/s, rigid stator). Set 3 to 4 times above; rolling
// on under the motor amplifies tenfold every few ms, so the scenes end
// before long rolling.
struct MotorAgreement {
  double position_m, speed_rad_per_s;
};
MotorAgreement motor_agreement(core::Method m) {
  if (m == core::Method::kSwitching) return {5e-9, 1e-6};
  if (m == core::Method::kIteration) return {1e-7, 1e-3};
  return {2e-6, 1e-3};
}

// rosenbrock4 under a motor drive differences its Jacobian (a forward
// difference of 1e-7 of each component, dense_rodasp.hpp), the Jeffcott's
// and the rotor file's in their own coordinates: the two runs agree to the
// integration's error, not to rounding. At rtol 1e-9 (the scene's 1e-6 left
// 8e-8 m and 2e-4 rad/s) they agree within 3e-8 m (8.6e-9 m measured: a
// rigid stator's rebounds) and 1e-4 rad/s (2.3e-5 measured). Returns
// whether solver is rosenbrock4. (Under the prescribed drive both take the
// closed form and agree to rounding, below.)
constexpr double kRosenbrock4Agreement_m = 3e-8;
constexpr double kRosenbrock4SpeedAgreement_rad_per_s = 1e-4;
bool tighten_for_rosenbrock4(const test::Solver& solver, core::Scene& s) {
  if (solver.integrator != core::Integrator::kRosenbrock4) return false;
  s.solver.rtol = 1e-9;
  s.solver.atol = 1e-12;
  return true;
}

}  // namespace

namespace {
// Every solver (Jeffcott and file scene alike): a case each.
class JeffcottAsRotorFile : public ::testing::TestWithParam<test::Solver> {};

// How far the Jeffcott's run and the one-node file's stay apart, per solver:
// positions, and the drive's torque. To rounding carried through the rub's
// events (1e-13 m; 6.6e-15 m measured), but:
// Iteration on dop853 differences the jerk of its dense output over
// 1e-6 s (kHermiteJerkStep_s), which turns the forces' rounding (1e-16
// of them) into 1e-10 of the jerk; the lift-offs located on that dense
// output, and the steps redone to end on them, carry it into the
// trajectory: there the runs agree to 3e-9 m (1.1e-9 measured; at this
// rtol 1e-6 other last bits moved golden runs by up to 6.5e-9 m,
// test_golden.cpp; 0 on dopri5, 6.6e-15 where the jerk is in closed
// form).
// rosenbrock4's Jacobian, the same in closed form but for rounding,
// and its stiff contact spring carry the forces' rounding further: 1e-12
// m (3.8e-13 measured).
// The torques as the positions: to rounding, 1e-12 N m (3e-14
// measured); 1e-8 N m on iteration's differenced jerk (4.7e-9); on
// rosenbrock4 1e-7 of the largest (1.3e-8: the contact spring, k_c 1e9
// N/m, turns the positions' 4e-13 m into its force's difference).
struct FileAgreement {
  double position_m;
  double torque_N_m;             // absolute
  double torque_of_largest = 0;  // relative to the largest torque, where the contact spring sets it
};
FileAgreement file_agreement(const test::Solver& solver) {
  if (solver.method == core::Method::kIteration &&
      (solver.integrator == core::Integrator::kDop853 || solver.integrator == core::Integrator::kDop853Rosenbrock4))
    return {3e-9, 1e-8};  // the differenced jerk (the Jeffcott's flight is not stiff: dop853's throughout)
  // The rigid methods' free flight on RODASP: the fixed-size and the block
  // solve round differently, so a step accepted on one side and rejected on
  // the other sends the runs on step paths of their own, which agree to the
  // tolerance (switching, the rigid stator's bouncing scene: 7.2e-9 m at
  // rtol 1e-6, 1.9e-12 m at 1e-9, measured, the torque 2.8e-6 of its
  // largest; iteration 3.0e-9 m, the torque 5.0e-7 of its largest).
  if (solver.method != core::Method::kPenalty && solver.integrator == core::Integrator::kRosenbrock4)
    return {3e-8, 0.0, 1e-5};
  if (solver.integrator == core::Integrator::kRosenbrock4) return {1e-12, 0.0, 1e-7};
  return {1e-13, 1e-12};  // rounding
}
}  // namespace

// The paper's run-up (4 s through the critical speed into rub) with the
// Jeffcott given as a one-node rotor file: the station alone (1 planar
// mode) is the same equations with the forces summed in another order
// (-K q - C q' + f in matrix form), so the runs agree to rounding carried
// through the rub's events: 1e-13 m (6.6e-15 m measured).
// Beyond the paper's scene: bouncing impacts (restitution 0.5, whose
// settling is judged from the rotor's free forces, the flexible model's
// here), high friction, a rigid stator with an offset (the methods' frame
// moved), a dopri5 run.

TEST_P(JeffcottAsRotorFile, RunsTheJeffcottsRun) {
  const test::Solver& solver = GetParam();
  const FileAgreement want = file_agreement(solver);
  std::vector<core::Scene> scenes(4, test::paper_scene());
  scenes[1].model.restitution = 0.5;
  scenes[1].model.friction_coefficient = 0.5;
  scenes[2].model.stator_model = core::StatorModel::kRigid;
  scenes[2].model.stator_offset_x_m = 0.5e-3;
  scenes[2].model.restitution = 0.3;
  scenes[3].solver.integrator = core::Integrator::kDopri5;
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    const bool penalty = solver.method == core::Method::kPenalty;
    if (penalty && i == 3) continue;  // dopri5 already
    core::Scene jeffcott_scene = scenes[i];
    jeffcott_scene.solver.method = solver.method;
    if (i != 3) jeffcott_scene.solver.integrator = solver.integrator;
    if (penalty) jeffcott_scene.end_time_s = 2.0;  // through the first rub
    core::Scene file = jeffcott_scene;
    file.rotor = jeffcott_file_scene(1).rotor;
    // The whole train's J (J_G + m e^2, the motor run's below): not in the
    // motion, in the drive's torque.
    file.model.rotor_polar_inertia_kg_m2 += file.model.rotor_mass_kg * std::pow(file.model.eccentricity_m, 2);
    const test::Run jeffcott = test::run(jeffcott_scene);
    const test::Run flexible = test::run(file);
    ASSERT_FALSE(jeffcott.result.failure) << failure_of(jeffcott);
    ASSERT_FALSE(flexible.result.failure) << solver.name() << " " << i << ": " << failure_of(flexible);
    ASSERT_GE(jeffcott.out.events.size(), penalty ? 1u : 5u) << i;  // the rub: touchdowns, lift-offs
    // The drive's torque: the Jeffcott's J_G A - R_r F_t - e F . u, the
    // file's J A - R_r F_t - h^T q'' (flexible_rotor_model.hpp), equal.
    double torque_N_m = 0.0, largest_N_m = 0.0;
    for (std::size_t k = 0; k < std::min(jeffcott.out.samples.size(), flexible.out.samples.size()); ++k) {
      torque_N_m = std::max(
          torque_N_m, std::abs(jeffcott.out.samples[k].drive_torque_N_m - flexible.out.samples[k].drive_torque_N_m));
      largest_N_m = std::max(largest_N_m, std::abs(jeffcott.out.samples[k].drive_torque_N_m));
    }
    std::printf("%s scene %zu: torque %.3g of %.3g N m\n", solver.name().c_str(), i, torque_N_m, largest_N_m);
    EXPECT_EQ(flexible.out.events.size(), jeffcott.out.events.size()) << solver.name() << " " << i;
    const double d = max_position_difference(jeffcott, flexible);
    std::printf("%s scene %zu: positions %.3g m\n", solver.name().c_str(), i, d);
    EXPECT_LT(d, want.position_m) << solver.name() << " " << i;
    EXPECT_LT(torque_N_m, want.torque_N_m + want.torque_of_largest * largest_N_m) << solver.name() << " " << i;
  }
}

// The same under a motor drive (the spin a state, the unbalance's lever
// coupling it to the station, docs/rotor_theory.md): the file's train inertia is
// the Jeffcott's about its mass centre plus m e^2, so that J_eff = J - (m
// e)^2 / m_st is the Jeffcott's J_G. At constant reference speed: the
// motor's feed-forward J A_ref would otherwise differ by m e^2 A_ref (the
// two scenes' inertias), a real difference of 3e-5 rad/s on the run-up.
// Far above the critical speed (600 rad/s, 4.6 times it): grazes, impacts
// and rolling (friction 0.3, as test_cvode_switching's rolling scene);
// impacts with spin that rebound (restitution 0.5, friction 0.5: the
// incremental impact law); a rigid stator with rebounds; gravity (the file's
// weight at the node turns the spin through the lever, the unbalance's own
// weight back: flexible_rotor_model.hpp; the Jeffcott's weight at its mass
// centre has no torque). The runs agree to
// the forces' rounding carried through the rub's events. (The modes' share
// of the spin: test_flexible_rotor_energy.cpp.)
TEST_P(JeffcottAsRotorFile, RunsTheJeffcottsMotorRun) {
  const test::Solver& solver = GetParam();
  std::vector<core::Scene> scenes(4, test::paper_scene());
  scenes[0].model.friction_coefficient = 0.3;
  scenes[3].model.gravity_m_per_s2 = 9.81;
  scenes[3].model.friction_coefficient = 0.2;
  scenes[1].model.restitution = 0.5;
  scenes[1].model.friction_coefficient = 0.5;
  scenes[2].model.stator_model = core::StatorModel::kRigid;
  scenes[2].model.restitution = 0.3;
  for (core::Scene& s : scenes) {
    s.model.drive_model = core::DriveModel::kMotor;
    s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = 600.0;
    s.end_time_s = 0.15;
  }
  scenes[1].end_time_s = 0.07;
  for (std::size_t i = 0; i < scenes.size(); ++i) {
    core::Scene jeffcott_scene = scenes[i];
    jeffcott_scene.solver.method = solver.method;
    jeffcott_scene.solver.integrator = solver.integrator;
    const bool coordinates_differ = tighten_for_rosenbrock4(solver, jeffcott_scene);
    core::Scene file = jeffcott_scene;
    file.rotor = jeffcott_file_scene(1).rotor;
    const double me = file.model.rotor_mass_kg * file.model.eccentricity_m;
    file.model.rotor_polar_inertia_kg_m2 += me * file.model.eccentricity_m;
    const test::Run jeffcott = test::run(jeffcott_scene);
    const test::Run flexible = test::run(file);
    ASSERT_FALSE(jeffcott.result.failure) << failure_of(jeffcott);
    ASSERT_FALSE(flexible.result.failure) << solver.name() << " " << i << ": " << failure_of(flexible);
    ASSERT_GE(jeffcott.out.events.size(), 7u) << i;
    EXPECT_EQ(flexible.out.events.size(), jeffcott.out.events.size()) << solver.name() << " " << i;
    double speed = 0.0;
    for (std::size_t k = 0; k < std::min(jeffcott.out.samples.size(), flexible.out.samples.size()); ++k) {
      speed = std::max(speed, std::abs(jeffcott.out.samples[k].drive.speed_rad_per_s -
                                       flexible.out.samples[k].drive.speed_rad_per_s));
    }
    const double d = max_position_difference(jeffcott, flexible);
    std::printf("%s scene %zu: positions %.3g m, speed %.3g rad/s\n", solver.name().c_str(), i, d, speed);
    const MotorAgreement want = coordinates_differ
                                    ? MotorAgreement{kRosenbrock4Agreement_m, kRosenbrock4SpeedAgreement_rad_per_s}
                                    : motor_agreement(solver.method);
    EXPECT_LT(d, want.position_m) << solver.name() << " " << i;
    EXPECT_LT(speed, want.speed_rad_per_s) << solver.name() << " " << i;
  }
}

INSTANTIATE_TEST_SUITE_P(AllSolvers, JeffcottAsRotorFile, ::testing::ValuesIn(test::all_solvers()),
                         [](const auto& info) { return info.param.name(); });

// With its tilts kept as modal coordinates (2 planar modes) the rotor is
// still the Jeffcott (the tilts are uncoupled and unforced, so the station
// moves as the Jeffcott's),
// but the state has 4 more entries, which dop853's RMS error norm counts:
// the steps differ, so the runs agree to the tolerance's level, not to
// rounding: rtol 1e-9 of the 2e-3 m orbit is 2e-12 m a step, 1e-9 m over
// the run's ~1e5 steps at most (6.8e-11 m measured).
TEST(FlexibleRotorRuns, UncoupledModesChangeNothingButTheSteps) {
  core::Scene jeffcott_scene = test::paper_scene();
  jeffcott_scene.solver.rtol = 1e-9;
  jeffcott_scene.solver.atol = 1e-12;
  core::Scene flexible_scene = jeffcott_file_scene(2);
  flexible_scene.solver.rtol = 1e-9;
  flexible_scene.solver.atol = 1e-12;
  const test::Run jeffcott = test::run(jeffcott_scene);
  const test::Run flexible = test::run(flexible_scene);
  ASSERT_FALSE(flexible.result.failure) << failure_of(flexible);
  EXPECT_EQ(flexible.out.events.size(), jeffcott.out.events.size());
  const double d = max_position_difference(jeffcott, flexible);
  EXPECT_LT(d, 1e-9);
}

namespace {

// The isotropic seal rotor at a constant 300 rad/s against a rigid seal of
// 20 um clearance (test/data/rotors/isotropic_seal.yaml), from rest.
core::Scene isotropic_full_rub_scene(long planar_modes) {
  core::Scene s;
  s.rotor.file = test::source_path("test/data/rotors/isotropic_seal.yaml");
  s.rotor.planar_modes = planar_modes;
  s.model.stator_model = core::StatorModel::kRigid;
  s.model.clearance_m = 20e-6;
  s.model.friction_coefficient = 0.1;
  s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = 300.0;
  s.end_time_s = 2.0;
  s.output_rate_hz = 100.0;
  s.solver.rtol = 1e-9;
  s.solver.atol = 1e-12;
  return s;
}

}  // namespace

// The synchronous full annular rub of a multi-DOF rotor: from rest the
// rotor settles (in 2 s, ~100 of its slowest decay times) onto the forward
// full rub whose normal force and station orbit the closed form gives
// through the full FE model's receptance (rotor_steady_response.hpp). What
// is left is the truncation of the reduced model: with 4 planar modes (of
// 26) 9.2e-4 of N, with 8 1.1e-5 (measured). With 12 and more this full rub
// is no longer the attractor at f = 0.1 (a shaft mode at 2.4 kHz that the
// friction makes flutter: FullRubStability.TheSealRotorFluttersWithTwelve
// ModesAndMore), so 8 is the test's model.
namespace {
class FullAnnularRub : public ::testing::TestWithParam<test::Solver> {};
// N at 8 planar modes within kFullRubForce of the closed form (the
// truncation, above), and the station within kFullRubStation of the clearance.
constexpr double kFullRubForce = 3e-5;
constexpr double kFullRubStation = 1e-4;
// On the bore: by construction (switching), projected each step (iteration).
constexpr double kOnTheBore_m = 1e-12;
}  // namespace

TEST_P(FullAnnularRub, SettlesOntoTheClosedForm) {
  const test::Solver& solver = GetParam();
  const core::FeRotor rotor = core::load_rotor_file(test::source_path("test/data/rotors/isotropic_seal.yaml"));
  const double w = 300.0, f = 0.1, c = 20e-6;
  const auto branches = core::synchronous_full_rub(core::assemble(rotor), rotor.rub_station_node, rotor.unbalances,
                                                   core::StationStator{}, c, f, w);
  ASSERT_FALSE(branches.empty());
  const core::FlexibleFullRub& want = branches.front();
  std::vector<double> force_error, station_error_m;
  for (const long modes : {4L, 8L}) {
    core::Scene s = isotropic_full_rub_scene(modes);
    s.solver.method = solver.method;
    s.solver.integrator = solver.integrator;
    const test::Run r = test::run(s);
    ASSERT_FALSE(r.result.failure) << solver.name() << ": " << failure_of(r);
    const core::Sample& end = r.out.samples.back();
    ASSERT_TRUE(end.in_contact) << solver.name() << " " << modes;
    EXPECT_NEAR(end.kin.rotor_pos.norm(), c, kOnTheBore_m) << solver.name() << " " << modes;
    const std::complex<double> z = want.station_m * std::exp(std::complex<double>(0.0, w * end.t_s));
    force_error.push_back(std::abs(end.normal_force_N / want.normal_force_N - 1.0));
    station_error_m.push_back(std::abs(std::complex<double>(end.kin.rotor_pos.x(), end.kin.rotor_pos.y()) - z));
  }
  EXPECT_LT(force_error[1], kFullRubForce) << solver.name();
  EXPECT_LT(force_error[1], force_error[0] / 10.0) << solver.name();  // truncation: more modes, closer
  EXPECT_LT(station_error_m[1], kFullRubStation * c) << solver.name();
}

INSTANTIATE_TEST_SUITE_P(RigidMethods, FullAnnularRub, ::testing::ValuesIn(test::rigid_solvers()),
                         [](const auto& info) { return info.param.name(); });

// The penalty method's full rub is the rigid one's with the contact spring
// k_c in series: in steady full rub delta' = 0, so the contact's damper is
// idle and the friction slides at f F_n, and the spring is a massless
// "stator" of receptance 1 / k_c (StationStator: elastic, no mass, k_c).
// With 8 planar modes, after 1.5 s from rest: N within 3e-5 of that closed
// form (1.7e-5 measured: the truncation, as the rigid methods'), which
// differs from the rigid contact's by 1e-3. On dopri5 and on rosenbrock4.
void penalty_settles_onto_the_full_rub(core::Integrator integrator);  // below

TEST(FlexibleRotorRuns, PenaltySettlesOntoTheFullRubWithItsContactSpring) {
  for (const core::Integrator integrator : {core::Integrator::kDopri5, core::Integrator::kRosenbrock4}) {
    SCOPED_TRACE(core::to_string(integrator));
    penalty_settles_onto_the_full_rub(integrator);
  }
}

void penalty_settles_onto_the_full_rub(core::Integrator integrator) {
  const core::FeRotor rotor = core::load_rotor_file(test::source_path("test/data/rotors/isotropic_seal.yaml"));
  core::Scene s = isotropic_full_rub_scene(8);
  s.solver.method = core::Method::kPenalty;
  s.solver.integrator = integrator;
  if (integrator == core::Integrator::kRosenbrock4) {
    // Its differenced Jacobian makes rtol 1e-9 four times dopri5's time; at
    // rtol 1e-6 N is 1.64e-5 off (1.71e-5 on dopri5 at 1e-9): the truncation.
    s.solver.rtol = 1e-6;
    s.solver.atol = 1e-10;
  }
  s.end_time_s = 1.5;
  core::StationStator spring;
  spring.rigid = false;
  spring.stiffness_N_per_m = s.model.contact_stiffness_N_per_m;
  const auto with_spring = core::synchronous_full_rub(core::assemble(rotor), rotor.rub_station_node, rotor.unbalances,
                                                      spring, s.model.clearance_m, s.model.friction_coefficient, 300.0);
  const auto rigid =
      core::synchronous_full_rub(core::assemble(rotor), rotor.rub_station_node, rotor.unbalances, core::StationStator{},
                                 s.model.clearance_m, s.model.friction_coefficient, 300.0);
  ASSERT_FALSE(with_spring.empty());
  ASSERT_FALSE(rigid.empty());
  const test::Run r = test::run(s);
  ASSERT_FALSE(r.result.failure) << failure_of(r);
  const core::Sample& end = r.out.samples.back();
  ASSERT_TRUE(end.in_contact);
  const double n_want = with_spring.front().normal_force_N;
  EXPECT_NEAR(end.normal_force_N / n_want, 1.0, 3e-5);
  EXPECT_GT(std::abs(rigid.front().normal_force_N / n_want - 1.0), 3e-4);  // the spring shows
  EXPECT_NEAR(end.penetration_m, n_want / s.model.contact_stiffness_N_per_m,
              1e-3 * n_want / s.model.contact_stiffness_N_per_m);
}

// The seal-rub example (config/seal_rub_runup.yaml): a run-up of the
// flexible rotor through its first critical speed (240.7 rad/s, forward whirl) into rub
// at the seal. The first contact comes near the critical speed, the rub is
// sustained for a while, and the run keeps the method's promises: the same
// events at any output rate, bit for bit, and the same run twice.
void seal_rub_promises(core::Scene s);  // below

class SealRubRunUp : public ::testing::TestWithParam<test::Solver> {};

TEST_P(SealRubRunUp, KeepsTheMethodsPromises) {
  core::Scene s = core::load_scene(test::source_path("config/seal_rub_runup.yaml"));
  s.solver.method = GetParam().method;
  s.solver.integrator = GetParam().integrator;
  seal_rub_promises(s);
}

INSTANTIATE_TEST_SUITE_P(AllSolvers, SealRubRunUp, ::testing::ValuesIn(test::all_solvers()),
                         [](const auto& info) { return info.param.name(); });

// The two rigid methods model the same contact, so on the seal-rub run-up
// at a tight tolerance they find the same events, of the same kinds, and the
// same orbit (kOrbitAgreement_m). A crossing is as well defined as the gap
// that crosses: orbits kOrbitAgreement_m apart cross at a closing speed v
// up to kOrbitAgreement_m / v apart in time, on top of the 1e-7 s every
// event is held to (a lift-off, a touchdown after a flight: 1e-8 s measured).
// That matters for a touchdown right after a plastic graze: the rotor
// leaves the graze with zero normal velocity and its gap comes back nearly
// tangentially (at 3.4e-7 m/s: 3e-5 s; the two methods 1.1e-5 s apart there
// once the iteration's jerk kept to the pressed side of its lift-offs).
TEST(FlexibleRotorRuns, SwitchingAndIterationAgreeOnTheSealRub) {
  core::Scene s = core::load_scene(test::source_path("config/seal_rub_runup.yaml"));
  s.solver.rtol = 1e-9;
  s.solver.atol = 1e-12;
  const test::Run switching = test::run(s);
  s.solver.method = core::Method::kIteration;
  const test::Run iteration = test::run(s);
  ASSERT_FALSE(switching.result.failure) << failure_of(switching);
  ASSERT_FALSE(iteration.result.failure) << failure_of(iteration);
  ASSERT_EQ(iteration.out.events.size(), switching.out.events.size());
  constexpr double kOrbitAgreement_m = 1e-11;
  for (std::size_t i = 0; i < switching.out.events.size(); ++i) {
    EXPECT_EQ(iteration.out.events[i].kind, switching.out.events[i].kind) << i;
    const double closing_m_per_s = switching.out.events[i].normal_velocity_m_per_s;
    const double bound_s = 1e-7 + (closing_m_per_s > 0.0 ? kOrbitAgreement_m / closing_m_per_s : 0.0);
    EXPECT_NEAR(iteration.out.events[i].t_s, switching.out.events[i].t_s, bound_s) << i;
  }
  EXPECT_LT(max_position_difference(switching, iteration), kOrbitAgreement_m);
}

// The seal rotor's ringing rub at 16 planar modes to 1.65 s, by a method on
// dop853 and on rosenbrock4 (the two tests below).
struct RingingSealRuns {
  test::Run dop853, rodasp;
  double atol_m;  // the scene's
};
RingingSealRuns ringing_seal_runs(core::Method method) {
  core::Scene s = core::load_scene(test::source_path("config/seal_rub_runup.yaml"));
  s.rotor.planar_modes = 16;
  s.end_time_s = 1.65;
  s.solver.method = method;
  s.solver.integrator = core::Integrator::kDop853;
  test::Run dop853 = test::run(s);
  s.solver.integrator = core::Integrator::kRosenbrock4;
  return {std::move(dop853), test::run(s), s.solver.atol};
}

// Switching on rosenbrock4 (RODASP in free flight) through the seal rotor's
// ringing rub at 16 planar modes, where the contact breaks into hundreds of
// short touchdowns (675 events to 1.65 s): it runs through, on the same
// events as dop853 (both at rtol 1e-6), the orbit within kOrbit_m (4.1e-11 m
// measured). An event's time within kEvent_s (lift-offs and touchdowns
// moved by up to 5.2e-7 s), and a touchdown closing at v within kGap_m / v
// more, the time a gap that far off takes to close (the slowest, at 9e-8
// m/s, moved by 2.1e-6 s: 1.9e-13 m). Restarted at an event from a step
// taken again to end there, off the surface by the step's local error, a
// graze fired again at once and the run stalled at 1.6016 s (the chatter
// guard).
TEST(FlexibleRotorRuns, SwitchingOnRosenbrock4RunsTheRingingSealRub) {
  constexpr double kEvent_s = 1e-6;
  constexpr double kGap_m = 1e-12;
  constexpr double kOrbit_m = 1e-9;
  const auto [dop853, rodasp, atol_m] = ringing_seal_runs(core::Method::kSwitching);
  ASSERT_FALSE(dop853.result.failure) << failure_of(dop853);
  ASSERT_FALSE(rodasp.result.failure) << failure_of(rodasp);
  ASSERT_GT(dop853.out.events.size(), 400u);
  ASSERT_EQ(rodasp.out.events.size(), dop853.out.events.size());
  for (std::size_t i = 0; i < dop853.out.events.size(); ++i) {
    const core::ContactEvent& want = dop853.out.events[i];
    EXPECT_EQ(rodasp.out.events[i].kind, want.kind) << i;
    const double closing_m_per_s = want.normal_velocity_m_per_s;
    EXPECT_NEAR(rodasp.out.events[i].t_s, want.t_s, kEvent_s + (closing_m_per_s > 0.0 ? kGap_m / closing_m_per_s : 0.0))
        << i << " " << core::to_string(want.kind) << " closing at " << closing_m_per_s << " m/s";
  }
  EXPECT_LT(max_position_difference(dop853, rodasp), kOrbit_m);
}

// The iteration method on rosenbrock4 (RODASP in free flight, dop853
// engaged) through the same ringing rub: its touchdowns are resolved to the
// gap tolerance atol over the closing speed (a free step ends within atol of
// the bore), so the chatter's hundreds of short contacts part from dop853's
// event by event (they are 2e-4 of the orbit deep), but the first contact
// agrees to twice that resolution (1.1e-6 s of 2.0e-6 measured), both ring
// (334 and 339 touchdowns measured), and the orbits agree to kOrbit_m (4.0e-9
// m measured, of 20 um).
TEST(FlexibleRotorRuns, IterationOnRosenbrock4RunsTheRingingSealRub) {
  constexpr double kOrbit_m = 1e-8;
  constexpr long kRinging = 300;  // touchdowns: the contact rings the modes
  const auto [dop853, rodasp, atol_m] = ringing_seal_runs(core::Method::kIteration);
  ASSERT_FALSE(dop853.result.failure) << failure_of(dop853);
  ASSERT_FALSE(rodasp.result.failure) << failure_of(rodasp);
  ASSERT_FALSE(dop853.out.events.empty());
  ASSERT_FALSE(rodasp.out.events.empty());
  const core::ContactEvent& first = dop853.out.events.front();
  EXPECT_NEAR(rodasp.out.events.front().t_s, first.t_s, 2.0 * atol_m / first.normal_velocity_m_per_s);
  EXPECT_GT(dop853.result.stats.touchdowns, kRinging);
  EXPECT_GT(rodasp.result.stats.touchdowns, kRinging);
  EXPECT_LT(max_position_difference(dop853, rodasp), kOrbit_m);
}

void seal_rub_promises(core::Scene s) {
  const test::Run a = test::run(s);
  ASSERT_FALSE(a.result.failure) << failure_of(a);
  ASSERT_FALSE(a.out.events.empty());
  const double first_contact_speed = 150.0 + 70.0 * a.out.events.front().t_s;
  EXPECT_GT(first_contact_speed, 200.0);
  EXPECT_LT(first_contact_speed, 241.0);
  EXPECT_TRUE(std::any_of(a.out.events.begin(), a.out.events.end(),
                          [](const core::ContactEvent& e) { return e.kind == core::EventKind::kTouchdown; }));
  const test::Run again = test::run(s);
  s.output_rate_hz = 250.0;
  const test::Run slower = test::run(s);
  for (const test::Run* other : {&again, &slower}) {
    ASSERT_EQ(other->out.events.size(), a.out.events.size());
    for (std::size_t i = 0; i < a.out.events.size(); ++i) {
      EXPECT_EQ(other->out.events[i].t_s, a.out.events[i].t_s) << i;
      EXPECT_EQ(other->out.events[i].impulse_N_s, a.out.events[i].impulse_N_s) << i;
    }
  }
  EXPECT_EQ(again.out.samples.back().kin.rotor_pos, a.out.samples.back().kin.rotor_pos);
}

// A crossing between two points where the function is below zero at both:
// g = 0.01 - (t - 0.5)^2 on [0, 1] rises through zero at 0.4 and falls back
// at 0.6; the first root is found (to the locator's 1e-13 s). Lowered by
// 0.02 it stays below zero; a function that does not rise at the first
// point and fall at the second has no interior maximum to look at.
TEST(EventLocation, InteriorCrossingOfAGraze) {
  core::RunStats stats;
  auto graze = [](double t) { return 0.01 - (t - 0.5) * (t - 0.5); };
  EXPECT_NEAR(core::locate_interior_crossing(graze, 0.0, graze(0.0), 1.0, graze(1.0), 1e-4, stats), 0.4, 1e-12);
  auto short_of_it = [](double t) { return -0.01 - (t - 0.5) * (t - 0.5); };
  EXPECT_EQ(core::locate_interior_crossing(short_of_it, 0.0, short_of_it(0.0), 1.0, short_of_it(1.0), 1e-4, stats),
            std::numeric_limits<double>::infinity());
  auto falling = [](double t) { return -0.1 - t; };
  EXPECT_EQ(core::locate_interior_crossing(falling, 0.0, falling(0.0), 1.0, falling(1.0), 1e-4, stats),
            std::numeric_limits<double>::infinity());
}

// With 16 planar modes the seal rub rings: the normal force (the pressing,
// for the iteration method) falls to zero within a fraction of a step many
// times, and some of its minima dip below zero and back between two of the
// scan points. Those grazing lift-offs are located (an interior maximum of
// -N, locate_interior_crossing): unlocated, the switching method held the
// rotor on the bore by a pulling force, which a 20 kHz sample caught
// (-0.07 N at 1.76845 s, the run failed) and a 1 kHz sample did not (the
// run said ok). Located, the run holds its invariants at any output rate
// and keeps its events. (The iteration method clamps its force at zero, so
// a dip it missed shows in no sample; for it this checks the promise only.)
TEST(FlexibleRotorRuns, GrazingLiftOffsOfARingingContactAreLocated) {
  for (const core::Method method : {core::Method::kSwitching, core::Method::kIteration}) {
    core::Scene s = core::load_scene(test::source_path("config/seal_rub_runup.yaml"));
    s.solver.method = method;
    s.rotor.planar_modes = 16;
    s.end_time_s = 1.8;
    const test::Run coarse = test::run(s);
    s.output_rate_hz = 20000.0;
    const test::Run fine = test::run(s);
    SCOPED_TRACE(core::to_string(method));
    ASSERT_FALSE(coarse.result.failure) << failure_of(coarse);
    ASSERT_FALSE(fine.result.failure) << failure_of(fine);
    ASSERT_EQ(fine.out.events.size(), coarse.out.events.size());
    for (std::size_t i = 0; i < coarse.out.events.size(); ++i)
      EXPECT_EQ(fine.out.events[i].t_s, coarse.out.events[i].t_s);
    EXPECT_GT(coarse.out.events.size(), 100u);  // the ringing contact: a few hundred touchdowns
  }
}

// What runs a flexible rotor and what does not, each refusal naming the key.
TEST(FlexibleRotorRuns, ScenesItCannotRunAreRefusedNamingTheKey) {
  core::Scene s = core::load_scene(test::source_path("config/seal_rub_runup.yaml"));
  EXPECT_NO_THROW(core::validate_scene(s));
  auto refusal = [](core::Scene bad) -> std::string {
    try {
      core::validate_scene(bad);
    } catch (const core::SceneError& e) {
      return e.what();
    }
    return "";
  };
  core::Scene iteration = s;
  iteration.solver.method = core::Method::kIteration;
  EXPECT_NO_THROW(core::validate_scene(iteration));
  core::Scene penalty = s;
  penalty.solver.method = core::Method::kPenalty;
  penalty.solver.integrator = core::Integrator::kDopri5;
  EXPECT_NO_THROW(core::validate_scene(penalty));
  penalty.solver.integrator = core::Integrator::kAuto;  // rosenbrock4, as on the Jeffcott
  EXPECT_NO_THROW(core::validate_scene(penalty));
  EXPECT_EQ(core::effective_integrator(penalty), core::Integrator::kRosenbrock4);
  penalty.solver.integrator = core::Integrator::kRosenbrock4;
  EXPECT_NO_THROW(core::validate_scene(penalty));
  penalty.solver.integrator = core::Integrator::kRk4;  // below the rotor's bound (test_flexible_rk4.cpp)
  penalty.solver.fixed_step_s = 1e-6;
  EXPECT_NO_THROW(core::validate_scene(penalty));
  penalty.solver.fixed_step_s = 1e-3;
  EXPECT_NE(refusal(penalty).find("'fixed_step_s': value 0.001 is out of range"), std::string::npos)
      << refusal(penalty);
  core::Scene motor = s;
  motor.model.drive_model = core::DriveModel::kMotor;
  EXPECT_NO_THROW(core::validate_scene(motor));
  // The spin's inertia against the unbalances' lever (validate_flexible_spin):
  // on the Jeffcott's file (one unbalance m e at the station, 1 planar mode)
  // max h^T M^-1 h = m e^2 and the lever l = e, so the bound is the
  // Jeffcott's J_G bound f e (R_r + e) m plus m e^2.
  core::Scene jeffcott_motor = jeffcott_file_scene(1);
  jeffcott_motor.model.drive_model = core::DriveModel::kMotor;
  jeffcott_motor.model.friction_coefficient = 0.3;
  const double m = 0.418, e = 0.4e-3, r = 0.010;
  const double bound = m * e * e + 0.3 * e * (r + e) * m;
  jeffcott_motor.model.rotor_polar_inertia_kg_m2 = bound * (1.0 + 1e-9);
  EXPECT_NO_THROW(core::validate_scene(jeffcott_motor));
  jeffcott_motor.model.rotor_polar_inertia_kg_m2 = bound * (1.0 - 1e-9);
  EXPECT_NE(refusal(jeffcott_motor).find("'rotor_polar_inertia_kg_m2'"), std::string::npos) << refusal(jeffcott_motor);
  EXPECT_NE(refusal(jeffcott_motor).find("max h^T M^-1 h"), std::string::npos) << refusal(jeffcott_motor);
  // The bound's max over phi in closed form (the larger eigenvalue) against
  // a sweep on a rotor whose unbalances are not a quarter turn apart (the
  // cross term a^T M^-1 b is not zero): the sweep's 1e-4 rad misses the
  // peak by (1e-4)^2 of it at most.
  core::RotorSettings settings;
  settings.file = test::source_path("test/data/rotors/undamped_unbalanced_seal.yaml");
  settings.planar_modes = 6;
  const core::FlexibleRotorModel unbalanced = core::load_flexible_rotor(settings);
  const Eigen::LDLT<Eigen::MatrixXd> mass(unbalanced.rotor().matrices.M);
  double swept = 0.0;
  for (int i = 0; i < 62832; ++i) {
    const double phi = 1e-4 * i;
    const Eigen::VectorXd h = unbalanced.spin_lever(core::Vec2(std::cos(phi), std::sin(phi)));
    swept = std::max(swept, h.dot(mass.solve(h)));
  }
  EXPECT_GE(unbalanced.max_spin_lever_kg_m2(), swept * (1.0 - 1e-12));
  EXPECT_LE(unbalanced.max_spin_lever_kg_m2(), swept * (1.0 + 1e-8));
  core::Scene gravity = s;
  gravity.model.gravity_m_per_s2 = 9.81;
  EXPECT_NO_THROW(core::validate_scene(gravity));
  core::Scene missing = s;
  missing.rotor.file = "/nonexistent/rotor.yaml";
  EXPECT_NE(refusal(missing).find("'rotor_file'"), std::string::npos) << refusal(missing);
  core::Scene too_many = s;
  too_many.rotor.planar_modes = 20;  // the seal rotor has 26; the jeffcott file 2
  too_many.rotor.file = test::source_path("test/data/rotors/jeffcott_matrices.yaml");
  EXPECT_NE(refusal(too_many).find("rotor_planar_modes"), std::string::npos) << refusal(too_many);
  EXPECT_NE(refusal(too_many).find("1 to 2"), std::string::npos) << refusal(too_many);
  // The key itself: out of range named by set_scene_value.
  EXPECT_THROW(core::set_scene_value(s, "rotor_planar_modes", "513"), core::SceneError);  // above kMaxPlanarModes
}

// The probes read their node, not the rub station: a heavily damped rotor
// (test/data/rotors/damped_seal.yaml) at a constant 300 rad/s with no
// contact settles within 1 s onto its unbalance response, and the probe
// displacement at the file's first probe node (12, a bearing) and at a
// node asked for (rotor_probe_node 0, the other bearing) is the full FE
// model's response there, to the reduction's truncation: relative to the
// rotor's largest displacement (as rotor_rub_modal --study measures it),
// 3.9e-3 with 8 planar modes and 1.4e-4 with 16 (measured). Each method
// (on its default integrator here: the others share its model) gives the
// same.
TEST(FlexibleRotorRuns, ProbesReadTheirNodesResponse) {
  const std::string file = test::source_path("test/data/rotors/damped_seal.yaml");
  const core::FeRotor rotor = core::load_rotor_file(file);
  const double w = 300.0;
  const Eigen::VectorXcd full = core::unbalance_response(core::assemble(rotor), rotor.unbalances, w);
  double largest_m = 0.0;
  for (int node = 0; node < rotor.nodes(); ++node) {
    largest_m = std::max(largest_m, std::abs(full(core::dof_index(node, core::kDofX))));
  }
  for (const test::Solver& solver : {test::Solver{core::Method::kSwitching, core::Integrator::kDop853},
                                     test::Solver{core::Method::kIteration, core::Integrator::kDop853},
                                     test::Solver{core::Method::kPenalty, core::Integrator::kDopri5}}) {
    SCOPED_TRACE(solver.name());
    for (const long modes : {8L, 16L}) {
      if (modes == 16 && solver.method != core::Method::kSwitching) continue;  // the truncation: once
      for (const long probe_node : {-1L, 0L}) {
        core::Scene s;
        s.rotor.file = file;
        s.rotor.planar_modes = modes;
        s.rotor.probe_node = probe_node;
        s.solver.method = solver.method;
        s.solver.integrator = solver.integrator;
        s.model.stator_model = core::StatorModel::kRigid;
        s.model.clearance_m = 1e-3;  // never reached
        s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = w;
        s.end_time_s = 0.6;  // settled: at 1 s the errors below are the same to 3 digits
        s.output_rate_hz = 100.0;
        s.solver.rtol = 1e-7;
        s.solver.atol = 1e-11;
        const test::Run r = test::run(s);
        ASSERT_FALSE(r.result.failure) << failure_of(r);
        ASSERT_TRUE(r.out.events.empty());
        const core::Sample& end = r.out.samples.back();
        const int node = probe_node < 0 ? 12 : 0;
        const std::complex<double> turn = std::exp(std::complex<double>(0.0, w * end.t_s));
        const core::Vec2 want((full(core::dof_index(node, core::kDofX)) * turn).real(),
                              (full(core::dof_index(node, core::kDofY)) * turn).real());
        const double error = (end.probe_displacement_m - want).norm() / largest_m;
        EXPECT_LT(error, modes == 8 ? 1e-2 : 5e-4) << modes << " " << node;
        EXPECT_GT((end.probe_displacement_m - end.kin.rotor_pos).norm(), 0.5 * largest_m);  // not the station
      }
    }
  }
}

// ROSS's rub example as a scene (config/ross_rig_rub.yaml: ROSS's damped rig,
// 34 nodes, kyy/kxx = 115 at a bearing, its contact spring and damper in
// N s/m): the rub converges with the modes kept to the full FE model's (68
// planar modes; the docs' table). Bounds 5 to 16 times the measured
// differences for 16 modes and 1.75 to 10 times for 4 (the latter the older
// test's, 4 against 16), each run at the scene's rtol 1e-6: 16 planar modes within
// 1e-7 s of the full model's first contact (8.4e-9 s measured), 1e-6 s of
// its last contact's end (1.8e-7 s), 1e-4 of its peak normal force (6.7e-6)
// and 1e-5 of its orbit (6.2e-7); 4 within 1e-5 s (1.8e-6 s), 1e-4 s
// (5.7e-5 s), 5e-3 (2.0e-3) and 1e-3 (1.8e-4). The contact's damper is the
// scene's 40 N s/m, whatever the station's mass.
TEST(FlexibleRotorRuns, RossRigRubConvergesToTheFullModel) {
  core::Scene s = core::load_scene(test::source_path("config/ross_rig_rub.yaml"));
  s.output_rate_hz = 2000.0;
  struct Figures {
    double first_contact_s, last_contact_end_s, peak_force_N, orbit_m;
  };
  auto figures_of = [&](long modes) {
    s.rotor.planar_modes = modes;
    s.rotor.loaded = nullptr;
    const test::Run r = test::run(s);
    EXPECT_FALSE(r.result.failure) << modes << ": " << failure_of(r);
    EXPECT_FALSE(r.out.events.empty()) << modes;
    Figures f{r.out.events.empty() ? 0.0 : r.out.events.front().t_s,
              r.out.events.empty() ? 0.0 : r.out.events.back().t_s, 0.0, 0.0};
    for (const auto& x : r.out.samples) {
      f.peak_force_N = std::max(f.peak_force_N, x.normal_force_N);
      f.orbit_m = std::max(f.orbit_m, x.kin.rotor_pos.norm());
    }
    return f;
  };
  const Figures coarse = figures_of(4), fine = figures_of(16), full = figures_of(68);
  EXPECT_GT(full.peak_force_N, 1.0);
  EXPECT_NEAR(fine.first_contact_s, full.first_contact_s, 1e-7);
  EXPECT_NEAR(fine.last_contact_end_s, full.last_contact_end_s, 1e-6);
  EXPECT_NEAR(fine.peak_force_N / full.peak_force_N, 1.0, 1e-4);
  EXPECT_NEAR(fine.orbit_m / full.orbit_m, 1.0, 1e-5);
  EXPECT_NEAR(coarse.first_contact_s, full.first_contact_s, 1e-5);
  EXPECT_NEAR(coarse.last_contact_end_s, full.last_contact_end_s, 1e-4);
  EXPECT_NEAR(coarse.peak_force_N / full.peak_force_N, 1.0, 5e-3);
  EXPECT_NEAR(coarse.orbit_m / full.orbit_m, 1.0, 1e-3);
  std::printf(
      "ROSS's rig rub, 4 / 16 planar modes against the full model: first contact %.2e / %.2e s, last end "
      "%.2e / %.2e s, force %.2e / %.2e, orbit %.2e / %.2e\n",
      std::abs(coarse.first_contact_s - full.first_contact_s), std::abs(fine.first_contact_s - full.first_contact_s),
      std::abs(coarse.last_contact_end_s - full.last_contact_end_s),
      std::abs(fine.last_contact_end_s - full.last_contact_end_s),
      std::abs(coarse.peak_force_N / full.peak_force_N - 1.0), std::abs(fine.peak_force_N / full.peak_force_N - 1.0),
      std::abs(coarse.orbit_m / full.orbit_m - 1.0), std::abs(fine.orbit_m / full.orbit_m - 1.0));
  EXPECT_EQ(core::Simulation(s).contact_point().contact_damping_N_s_per_m, 40.0);
}

// rotor_planar_modes auto (rotor_truncation_tolerance 1e-3): the fewest planar
// modes whose unbalance response at the station and the probe nodes is
// within the tolerance of the full FE model's over the scene's speeds, one
// fewer is not (judged here by ResponseReference on the same 24 speeds and
// the flanks of the full model's critical speeds between them, found on a
// grid of its own); on the anisotropic rig (kyy/kxx = 115) run up from 100 to
// 400 rad/s. Its mode at 160.63 rad/s has a damping ratio of 4e-6: its
// resonance is far narrower than the grid's 13 rad/s; a run-up at the
// default 70 rad/s^2 passes it too fast to build that peak, one at 1e-3
// rad/s^2 builds much of it and needs more modes.
TEST(FlexibleRotorRuns, AutoModesAreTheFewestWithinTheTolerance) {
  core::Scene s;
  s.rotor.file = test::source_path("test/data/rotors/anisotropic_rig.yaml");
  s.rotor.planar_modes = 0;  // auto
  s.speed.initial_speed_rad_per_s = 100.0;
  s.speed.target_speed_rad_per_s = 400.0;
  const auto model = core::flexible_rotor_of(s);
  const core::TruncationReport& t = model->truncation();
  const long n = model->rotor().planar_modes;
  EXPECT_TRUE(t.chosen);
  EXPECT_EQ(t.min_speed_rad_per_s, 100.0);
  EXPECT_EQ(t.max_speed_rad_per_s, 400.0);
  const core::FeRotor rotor = core::load_rotor_file(s.rotor.file);
  const core::RotorMatrices full = core::assemble(rotor);
  std::vector<double> speeds, critical;
  for (int k = 0; k < 24; ++k) speeds.push_back(100.0 + 300.0 * k / 23);
  // Each critical speed's flanks w_c (1 -+ delta): the passage at the
  // scene's acceleration, or the mode's own damping ratio where larger.
  const double alpha = s.speed.acceleration_rad_per_s2;
  for (const core::CriticalSpeed& c : core::critical_speeds(full, 1000, 400.0, 200)) {
    if (c.speed_rad_per_s < 100.0) continue;
    critical.push_back(c.speed_rad_per_s);
    const double delta = std::max(c.damping_ratio, std::sqrt(2.0 * alpha / M_PI) / (2.0 * c.speed_rad_per_s));
    speeds.push_back(c.speed_rad_per_s * (1.0 - delta));
    speeds.push_back(c.speed_rad_per_s * (1.0 + delta));
  }
  ASSERT_EQ(t.critical_speeds_rad_per_s.size(), critical.size());
  for (std::size_t k = 0; k < critical.size(); ++k) {
    EXPECT_NEAR(t.critical_speeds_rad_per_s[k], critical[k], 1e-9 * critical[k]);  // located on either grid
  }
  std::vector<int> watched{rotor.rub_station_node};
  watched.insert(watched.end(), rotor.probe_nodes.begin(), rotor.probe_nodes.end());
  const core::ResponseReference reference(rotor, full, rotor.unbalances, speeds, watched);
  ASSERT_GT(n, 1);
  const double at_n = reference.error(core::reduce_rotor(rotor, full, rotor.rub_station_node, static_cast<int>(n)));
  // The critical speeds as located on the two grids agree to 1e-9 (above);
  // on a resonance of damping ratio 4e-6 that moves the response by up to
  // 1e-9 / 4e-6 = 2.5e-4 of itself.
  EXPECT_NEAR(at_n, t.response_error, 1e-3 * at_n);
  EXPECT_LE(at_n, 1e-3);
  EXPECT_GT(reference.error(core::reduce_rotor(rotor, full, rotor.rub_station_node, static_cast<int>(n - 1))), 1e-3);
  std::printf("anisotropic rig, 100 .. 400 rad/s: auto keeps %ld planar modes (error %.3g)\n", n, at_n);
  // A run-up slow enough to build most of that resonance's peak (1e-3
  // rad/s^2: its flanks 8e-5 of the speed away) needs more modes.
  core::Scene slow = s;
  slow.speed.acceleration_rad_per_s2 = 1e-3;
  const auto slow_model = core::flexible_rotor_of(slow);
  EXPECT_GT(slow_model->rotor().planar_modes, n);
  EXPECT_LE(slow_model->truncation().response_error, 1e-3);
  std::printf("the same at 1e-3 rad/s^2: %ld planar modes (error %.3g)\n", slow_model->rotor().planar_modes,
              slow_model->truncation().response_error);
  // What it cannot do, refused naming the key.
  auto refusal = [](const core::Scene& bad) -> std::string {
    try {
      core::validate_scene(bad);
    } catch (const core::SceneError& e) {
      return e.what();
    }
    return "accepted";
  };
  core::Scene none = s;  // at rest throughout: no response to judge by
  none.speed.initial_speed_rad_per_s = none.speed.target_speed_rad_per_s = 0.0;
  none.speed.acceleration_rad_per_s2 = 0.0;
  EXPECT_NE(refusal(none).find("scene key 'rotor_planar_modes': value auto needs the rotor file's unbalances and a "
                               "speed above 0"),
            std::string::npos)
      << refusal(none);
  core::Scene tight = s;
  tight.rotor.truncation_tolerance = 1e-16;
  tight.rotor.file = test::source_path("test/data/rotors/damped_seal.yaml");
  // Even the full model (26) is off by its rounding.
  EXPECT_NE(refusal(tight).find("value auto finds no model of 1 to 26 planar modes within rotor_truncation_tolerance "
                                "= 1e-16 (the best: "),
            std::string::npos)
      << refusal(tight);
}

// At the auto count the runs hold the unbalance response to the tolerance,
// in every method, without rub: the damped seal rotor at a constant 300
// rad/s, settled at 0.6 s (ProbesReadTheirNodesResponse), and ROSS's rig
// (34 nodes, kyy/kxx = 115 at a bearing, proportional damping) at 1200 rpm,
// settled at 8 s (its least damped mode decays by e in 0.9 s): the station
// and the first probe within the reduction's own judged error, plus 1e-4 of
// the largest displacement for what is left of the transient and the
// integration's error, of the full FE model's response.
namespace {

void auto_modes_hold_the_response(const std::string& file, double w, double settled_s) {
  const core::FeRotor rotor = core::load_rotor_file(file);
  const Eigen::VectorXcd full = core::unbalance_response(core::assemble(rotor), rotor.unbalances, w);
  double largest_m = 0.0;
  for (int node = 0; node < rotor.nodes(); ++node) {
    largest_m = std::max({largest_m, std::abs(full(core::dof_index(node, core::kDofX))),
                          std::abs(full(core::dof_index(node, core::kDofY)))});
  }
  for (const test::Solver& solver : {test::Solver{core::Method::kSwitching, core::Integrator::kDop853},
                                     test::Solver{core::Method::kIteration, core::Integrator::kDop853},
                                     test::Solver{core::Method::kPenalty, core::Integrator::kDopri5}}) {
    SCOPED_TRACE(solver.name());
    core::Scene s;
    s.rotor.file = file;
    s.rotor.planar_modes = 0;  // auto, 1e-3
    s.solver.method = solver.method;
    s.solver.integrator = solver.integrator;
    s.model.stator_model = core::StatorModel::kRigid;
    s.model.clearance_m = 1e-3;  // never reached
    s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = w;
    s.speed.acceleration_rad_per_s2 = 0.0;
    s.end_time_s = settled_s;
    s.output_rate_hz = 100.0;
    s.solver.rtol = 1e-7;
    s.solver.atol = 1e-11;
    core::Simulation sim(s);
    const core::Simulation::Reduction reduction = sim.reduction();
    EXPECT_LE(reduction.truncation.response_error, 1e-3);
    test::Collect out;
    ASSERT_TRUE(sim.advance_to(s.end_time_s, out)) << sim.failure()->message;
    ASSERT_TRUE(out.events.empty());
    const core::Sample& end = out.samples.back();
    const std::complex<double> turn = std::exp(std::complex<double>(0.0, w * end.t_s));
    auto want = [&](int node) {
      return core::Vec2((full(core::dof_index(node, core::kDofX)) * turn).real(),
                        (full(core::dof_index(node, core::kDofY)) * turn).real());
    };
    const double bound = reduction.truncation.response_error + 1e-4;
    std::printf("%s: auto keeps %ld planar modes (judged %.3g): station %.3g, probe %.3g\n", solver.name().c_str(),
                reduction.planar_modes, reduction.truncation.response_error,
                (end.kin.rotor_pos - want(rotor.rub_station_node)).norm() / largest_m,
                (end.probe_displacement_m - want(rotor.probe_nodes.front())).norm() / largest_m);
    EXPECT_LT((end.kin.rotor_pos - want(rotor.rub_station_node)).norm() / largest_m, bound)
        << reduction.planar_modes << " planar modes";
    EXPECT_LT((end.probe_displacement_m - want(rotor.probe_nodes.front())).norm() / largest_m, bound)
        << reduction.planar_modes << " planar modes";
  }
}

}  // namespace

TEST(FlexibleRotorRuns, AutoModesHoldTheUnbalanceResponseInEveryMethod) {
  struct Case {
    const char* file;
    double w_rad_per_s, settled_s;
  };
  for (const Case& c : {Case{"test/data/rotors/damped_seal.yaml", 300.0, 0.6},
                        Case{"config/rotors/ross_rub_rig.yaml", 125.66370614359172, 8.0}}) {
    SCOPED_TRACE(c.file);
    auto_modes_hold_the_response(test::source_path(c.file), c.w_rad_per_s, c.settled_s);
  }
}
