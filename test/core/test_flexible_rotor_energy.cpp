// The energy and momentum balances of a flexible rotor in rub (issue 28).
// Energy: a rotor with
// nothing that gives or takes energy (test/data/rotors/undamped_seal.yaml: no
// damping, no unbalance, symmetric stiffness) spinning at a constant speed
// and set moving against the seal keeps its energy through every impact and
// flight, in every method: elastic impacts (restitution 1) without friction
// take none, the gyroscopic forces (at 300 rad/s) do no work, and the
// penalty method's contact spring without damping gives back what it
// stored. The energy of q = [u; xi] (rotor_reduction.hpp) is
//   E = 1/2 q'^T M q' + 1/2 q^T K q   (+ the elastic stator's, + k_c's),
// read from the method's own state at each step's end (ContactMethod::
// modal_state), so a force in the seam that is not the model's (a
// non-symmetric K from a wrong projection, a G that is not skew, a station
// force counted twice) shows as a drift. With friction the energy falls at
// every slide, the friction's work, which the test checks for its sign.
// Momentum: at every impact of the rigid methods the contact impulse moves
// the station alone (its momentum jumps by the impulse; the modal
// coordinates and their velocities, which no contact force reaches, go on
// unchanged), and on an elastic stator rotor and stator exchange it (their
// sum is conserved).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "rotor_rub_sim/core/contact_method.hpp"
#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

core::Scene undamped_scene(const test::Solver& solver, core::StatorModel stator) {
  core::Scene s = core::load_scene(test::source_path("config/seal_rub_runup.yaml"));
  s.rotor.file = test::source_path("test/data/rotors/undamped_seal.yaml");
  s.rotor.planar_modes = 6;
  s.solver.method = solver.method;
  s.solver.integrator = solver.integrator;
  s.solver.rtol = 1e-10;
  s.solver.atol = 1e-14;
  s.model.restitution = 1.0;
  s.model.friction_coefficient = 0.0;
  s.model.stator_model = stator;
  s.model.stator_damping_N_s_per_m = 0.0;
  s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = 300.0;
  s.end_time_s = 0.1;
  return s;
}

struct Energies {
  std::vector<double> total_J;
  long events = 0;
};

// The energy of a state x with modal block [xi; xi'] [J]: the shaft's in
// q = [u; xi], an elastic stator's, the penalty method's contact spring's,
// and under a motor drive (or with_spin) the spin's terms 1/2 J w^2 - w
// h(phi)^T q' (Lagrange's kinetic energy with each unbalance a point mass).
double energy_J(const core::Scene& s, const core::FlexibleRotorModel& rotor, const core::Sample& x,
                const core::ModalState& modal, bool with_spin = false) {
  const int n = rotor.modal_size();
  Eigen::VectorXd q(n + 2), q_dot(n + 2);
  q << x.kin.rotor_pos, modal.head(n);
  q_dot << x.kin.rotor_vel, modal.tail(n);
  double e = 0.5 * q_dot.dot(rotor.rotor().matrices.M * q_dot) + 0.5 * q.dot(rotor.rotor().matrices.K * q);
  if (s.model.stator_model == core::StatorModel::kElastic) {
    e += 0.5 * s.model.stator_mass_kg * x.kin.stator_vel.squaredNorm() +
         0.5 * s.model.stator_stiffness_N_per_m * x.kin.stator_pos.squaredNorm();
  }
  if (s.solver.method == core::Method::kPenalty && x.penetration_m > 0.0) {
    e += 0.5 * s.model.contact_stiffness_N_per_m * x.penetration_m * x.penetration_m;
  }
  if (s.model.drive_model == core::DriveModel::kMotor || with_spin) {
    const double w = x.drive.speed_rad_per_s, phi = x.drive.angle_rad + s.model.unbalance_phase_rad;
    const Eigen::VectorXd h = rotor.spin_lever(core::Vec2(std::cos(phi), std::sin(phi)));
    e += 0.5 * s.model.rotor_polar_inertia_kg_m2 * w * w - w * h.dot(q_dot);
  }
  return e;
}

// Runs the method alone from the station at rest moving at v0 [m/s] (the
// modes at rest) and records the energy at every step's end.
Energies run_energy(const core::Scene& s, const core::Vec2& v0) {
  const core::FlexibleRotorModel rotor = core::load_flexible_rotor(s.rotor);
  const std::unique_ptr<core::ContactMethod> method = core::make_contact_method(s);
  const core::SpeedProfile profile(s.speed);
  core::Kinematics k = core::JeffcottModel(s.model).initial_kinematics(profile.at(0.0));
  k.rotor_vel = v0;
  method->start(0.0, k, profile.segment_at(0.0));
  auto energy = [&](double t) { return energy_J(s, rotor, method->sample(t), method->modal_state(t)); };
  Energies out;
  out.total_J.push_back(energy(0.0));
  std::vector<core::ContactEvent> events;
  while (method->step_end() < s.end_time_s) {
    method->step(s.end_time_s, events);
    out.total_J.push_back(energy(method->step_end()));
  }
  out.events = static_cast<long>(events.size());
  return out;
}

double worst_drift(const Energies& e) {
  double worst = 0.0;
  for (double x : e.total_J) worst = std::max(worst, std::abs(x / e.total_J.front() - 1.0));
  return worst;
}

}  // namespace

// The station set moving at 0.05 m/s: an orbit of tens of micrometres
// against the 20 um seal, 27 to 280 events in 0.1 s (30 turns at 300
// rad/s; 27 on the rigid seal). The energy's relative drift stays within the integrators' error
// at rtol 1e-10 over thousands of steps: 1e-8 for the rigid methods (1e-9
// measured), 1e-7 for the penalty method, whose contact spring takes
// thousands of steps more on dopri5 (3.2e-8 measured; 4.1e-10 on
// rosenbrock4, which the spring does not hold back). An impact that lost 1 % of
// its energy, a G that did work or a station force counted twice is
// orders of magnitude above either.
TEST(FlexibleRotorEnergy, ConservedThroughElasticFrictionlessRub) {
  for (const test::Solver& solver : test::all_solvers()) {
    for (const core::StatorModel stator : {core::StatorModel::kRigid, core::StatorModel::kElastic}) {
      SCOPED_TRACE(solver.name() + (stator == core::StatorModel::kRigid ? " rigid" : " elastic"));
      const Energies e = run_energy(undamped_scene(solver, stator), core::Vec2(0.05, 0.02));
      std::printf("%s %s: drift %.3g of the energy, %ld events\n", solver.name().c_str(),
                  stator == core::StatorModel::kRigid ? "rigid" : "elastic", worst_drift(e), e.events);
      EXPECT_GE(e.events, 20);
      EXPECT_LT(worst_drift(e), solver.method == core::Method::kPenalty ? 1e-7 : 1e-8);
    }
  }
}

// The rigid methods' impacts on the seal example's rotor (undamped here, so
// the bounces go on), from the station moving at 0.05 m/s, bouncing
// (restitution 0.5), on a rigid stator with friction (f = 0.3, spinning at
// 300 rad/s: the impulse has a tangential part) and on an elastic one
// without: at each impact event the state just before (the ending step's
// dense output at the event) and just after (the next step's start). The
// station's momentum jump along the contact normal is the event's normal
// impulse (1e-9 of it: both are the same rounding of one closed form), its
// tangential part lies in the friction cone, an elastic stator takes the opposite
// (the sum to the rounding of the momenta), and the positions and the modal
// block do not move (to 1e-12 of themselves: the ending step's interpolant
// at its end against the state it restarts from).
TEST(FlexibleRotorMomentum, ImpactsMoveTheStationAloneAndConserveMomentum) {
  for (const test::Solver& solver : test::rigid_solvers()) {
    for (const core::StatorModel stator : {core::StatorModel::kRigid, core::StatorModel::kElastic}) {
      SCOPED_TRACE(solver.name() + (stator == core::StatorModel::kRigid ? " rigid, f 0.3" : " elastic, f 0"));
      core::Scene s = undamped_scene(solver, stator);
      s.model.restitution = 0.5;
      s.model.friction_coefficient = stator == core::StatorModel::kRigid ? 0.3 : 0.0;
      s.end_time_s = 0.05;
      s.solver.rtol = 1e-8;  // an impact's balance is algebra at its instant: the integration's accuracy does not enter
      s.solver.atol = 1e-12;
      const core::FlexibleRotorModel rotor = core::load_flexible_rotor(s.rotor);
      const double m_st = rotor.station_mass_kg(), m_s = s.model.stator_mass_kg;
      const std::unique_ptr<core::ContactMethod> method = core::make_contact_method(s);
      const core::SpeedProfile profile(s.speed);
      core::Kinematics k = core::JeffcottModel(s.model).initial_kinematics(profile.at(0.0));
      k.rotor_vel = core::Vec2(0.05, 0.02);
      method->start(0.0, k, profile.segment_at(0.0));
      std::vector<core::ContactEvent> events;
      int impacts = 0;
      while (method->step_end() < s.end_time_s && !HasFatalFailure()) {
        const std::size_t before = events.size();
        method->step(s.end_time_s, events);
        if (events.size() == before || events.back().impulse_N_s <= 0.0) continue;
        const core::ContactEvent e = events.back();
        ASSERT_EQ(e.t_s, method->step_end());
        const core::Sample pre = method->sample(e.t_s);
        const core::ModalState modal_pre = method->modal_state(e.t_s);
        method->step(s.end_time_s, events);
        ASSERT_EQ(method->step_begin(), e.t_s);
        const core::Sample post = method->sample(e.t_s);
        const core::ModalState modal_post = method->modal_state(e.t_s);
        ++impacts;
        const core::Vec2 normal = (pre.kin.rotor_pos - pre.kin.stator_pos).normalized();  // stator to rotor
        const core::Vec2 tangent(-normal.y(), normal.x());
        const core::Vec2 rotor_jump = m_st * (post.kin.rotor_vel - pre.kin.rotor_vel);
        const core::Vec2 stator_jump = m_s * (post.kin.stator_vel - pre.kin.stator_vel);
        // Rounding: of the velocities and the impact's few dozen operations,
        // 1e-13 of the momenta they carry.
        const double rounding_N_s =
            1e-13 * (m_st * pre.kin.rotor_vel.norm() + m_s * pre.kin.stator_vel.norm() + e.impulse_N_s);
        EXPECT_NEAR(-rotor_jump.dot(normal), e.impulse_N_s, 1e-9 * e.impulse_N_s + rounding_N_s) << e.t_s;
        EXPECT_LE(std::abs(rotor_jump.dot(tangent)), s.model.friction_coefficient * e.impulse_N_s + rounding_N_s)
            << e.t_s;
        if (stator == core::StatorModel::kElastic) {
          EXPECT_LT((rotor_jump + stator_jump).norm(), rounding_N_s) << e.t_s;
        }
        // A touchdown places the station on the bore: within the gap's tolerance (atol).
        EXPECT_LT((post.kin.rotor_pos - pre.kin.rotor_pos).norm(), 10.0 * s.solver.atol) << e.t_s;
        EXPECT_LE((modal_post - modal_pre).cwiseAbs().maxCoeff(), 1e-12 * modal_pre.cwiseAbs().maxCoeff()) << e.t_s;
      }
      EXPECT_GT(impacts, 10);
    }
  }
}

// Under a motor drive the spin is a state, coupled to the shaft by the
// unbalances' lever (flexible_rotor_model.hpp): with the motor's torque nil
// (its limit 1e-15 N m) and large unbalances on both disks and at the
// station (test/data/rotors/undamped_unbalanced_seal.yaml), the spin and the
// shaft exchange energy and the sum
//   E = 1/2 q'^T M q' + 1/2 q^T K q + 1/2 J w^2 - w h(phi)^T q'
// (Lagrange's kinetic energy with each unbalance a point mass) is
// conserved through the elastic frictionless impacts, whose impulse moves
// the spin (the station's lever) and the modes with it (dxi' = h_xi dw).
// E is mostly the spin's 14 kJ, so the drift is taken against the energy
// the spin exchanges, J w max|w - w_0| (0.5 to 3.4 J here): within 1e-6 of
// it, the integrators' error at rtol 1e-10 (1.4e-7 measured, rkf78); leaving
// out the modes' share of an impact's spin jump alone drifts by 3.7e-5 of
// it (measured, switching, rigid stator).
TEST(FlexibleRotorEnergy, ConservedWithTheSpinFreeOnAnUnbalancedRotor) {
  for (const test::Solver& solver : test::all_solvers()) {
    for (const core::StatorModel stator : {core::StatorModel::kRigid, core::StatorModel::kElastic}) {
      SCOPED_TRACE(solver.name() + (stator == core::StatorModel::kRigid ? " rigid" : " elastic"));
      core::Scene s = undamped_scene(solver, stator);
      s.rotor.file = test::source_path("test/data/rotors/undamped_unbalanced_seal.yaml");
      s.model.drive_model = core::DriveModel::kMotor;
      s.model.drive_torque_limit_N_m = 1e-15;
      const core::FlexibleRotorModel rotor = core::load_flexible_rotor(s.rotor);
      const std::unique_ptr<core::ContactMethod> method = core::make_contact_method(s);
      const core::SpeedProfile profile(s.speed);
      core::Kinematics k = core::JeffcottModel(s.model).initial_kinematics(profile.at(0.0));
      k.rotor_vel = core::Vec2(0.05, 0.02);
      method->start(0.0, k, profile.segment_at(0.0));
      double e0 = NAN, worst_J = 0.0, speed_change = 0.0;
      std::vector<core::ContactEvent> events;
      auto check = [&](double t) {
        const core::Sample x = method->sample(t);
        const double e = energy_J(s, rotor, x, method->modal_state(t));
        if (std::isnan(e0)) e0 = e;
        worst_J = std::max(worst_J, std::abs(e - e0));
        speed_change = std::max(speed_change, std::abs(x.drive.speed_rad_per_s - s.speed.initial_speed_rad_per_s));
      };
      check(0.0);
      while (method->step_end() < s.end_time_s) {
        method->step(s.end_time_s, events);
        check(method->step_end());
      }
      const double exchanged_J = s.model.rotor_polar_inertia_kg_m2 * s.speed.initial_speed_rad_per_s * speed_change;
      std::printf("drift %.3g J of %.3g J exchanged with the spin, %zu events\n", worst_J, exchanged_J, events.size());
      EXPECT_GT(events.size(), 40u);
      EXPECT_GT(exchanged_J, 0.1);
      EXPECT_LT(worst_J, 1e-6 * exchanged_J);
    }
  }
}

// The prescribed drive's torque: it holds the speed against the torque the
// rotor's lateral motion puts on the spin, h^T q'' (flexible_rotor_model.hpp,
// the Jeffcott's e F . u), so its work is the change of the energy E above
// with the spin's terms: E(t) - E(0) = int_0^t T w dt. At a constant 300
// rad/s (T is then that lateral torque alone) on the unbalanced undamped
// rotor started at rest: in free flight (a 5 mm clearance) for every
// method, and through the seal's frictionless elastic rub for the penalty
// method, whose contact force is no impulse (a rigid impact's would be:
// the drive's torque is then impulsive, and the samples cannot integrate
// it). The work by the trapezoid rule on 100 kHz samples matches E within
// 1e-4 of the largest |E - E(0)|: 2.3e-7 measured in free flight (the
// rule's error, (w h)^2 / 12 of the 300 rad/s part, 8e-7), 3.1e-5 through
// the rub (the contact's faster motion). Without the lateral torque (the
// report before it was added: T = J A = 0) the work is nil against a
// change of E of 0.5 to 3.6 J.
TEST(FlexibleRotorEnergy, ThePrescribedDrivesTorqueDoesTheWork) {
  for (const test::Solver& solver : test::all_solvers()) {
    for (const bool rub : {false, true}) {
      if (rub && solver.method != core::Method::kPenalty) continue;
      SCOPED_TRACE(solver.name() + (rub ? " rub" : " free flight"));
      core::Scene s = undamped_scene(solver, core::StatorModel::kRigid);
      s.rotor.file = test::source_path("test/data/rotors/undamped_unbalanced_seal.yaml");
      if (!rub) s.model.clearance_m = 5e-3;
      s.solver.rtol = 1e-9;
      s.solver.atol = 1e-13;
      s.end_time_s = 0.05;
      const core::FlexibleRotorModel rotor = core::load_flexible_rotor(s.rotor);
      const std::unique_ptr<core::ContactMethod> method = core::make_contact_method(s);
      const core::SpeedProfile profile(s.speed);
      method->start(0.0, core::JeffcottModel(s.model).initial_kinematics(profile.at(0.0)), profile.segment_at(0.0));
      constexpr double kDt_s = 1e-5;
      double e0 = NAN, work_J = 0.0, last_power_W = 0.0, worst_J = 0.0, largest_change_J = 0.0;
      long k = 0;
      std::vector<core::ContactEvent> events;
      while (method->step_end() < s.end_time_s) {
        method->step(s.end_time_s, events);
        for (; k * kDt_s <= method->step_end(); ++k) {
          const double t = k * kDt_s;
          const core::Sample x = method->sample(t);
          const double e = energy_J(s, rotor, x, method->modal_state(t), true);
          const double power_W = x.drive_torque_N_m * x.drive.speed_rad_per_s;
          if (k == 0) {
            e0 = e;
          } else {
            work_J += 0.5 * kDt_s * (power_W + last_power_W);
          }
          last_power_W = power_W;
          worst_J = std::max(worst_J, std::abs(e - e0 - work_J));
          largest_change_J = std::max(largest_change_J, std::abs(e - e0));
        }
      }
      std::printf("%s%s: E - E(0) up to %.3g J, work against it within %.3g J, %zu events\n", solver.name().c_str(),
                  rub ? " rub" : "", largest_change_J, worst_J, events.size());
      EXPECT_GT(largest_change_J, 0.1);
      if (rub) {
        EXPECT_GT(events.size(), 4u);
      }
      EXPECT_LT(worst_J, 1e-4 * largest_change_J);
    }
  }
}

// Plastic impacts take energy (at 300 rad/s, frictionless); so does
// friction when nothing spins (at speed 0 the slide is the station's own
// motion along the bore; at speed the drive can feed the whirl through
// friction, so no sign is promised there), with bouncing impacts
// (restitution 0.5, f = 0.3). The energy never rises beyond the
// integrators' error (1e-6 of the start) and by the end has fallen by more
// than a tenth.
TEST(FlexibleRotorEnergy, PlasticImpactsAndFrictionWithoutSpinOnlyTakeEnergy) {
  for (const test::Solver& solver : test::all_solvers()) {
    for (const bool spinning : {true, false}) {
      SCOPED_TRACE(solver.name() + (spinning ? " plastic at 300 rad/s" : " friction at rest"));
      core::Scene s = undamped_scene(solver, core::StatorModel::kRigid);
      if (spinning) {
        s.model.restitution = 0.0;
      } else {
        s.model.restitution = 0.5;
        s.model.friction_coefficient = 0.3;
        s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = 0.0;
      }
      const Energies e = run_energy(s, core::Vec2(0.02, 0.01));
      double highest = e.total_J.front();
      for (double x : e.total_J) {
        EXPECT_LT(x, highest * (1.0 + 1e-6));
        highest = std::max(highest, x);
      }
      EXPECT_LT(e.total_J.back(), 0.9 * e.total_J.front());
    }
  }
}
