// Stability of the synchronous full annular rub (full_rub_stability.hpp):
// the equilibrium of the turning frame, the rigid stator's closed form, and
// the runs of the rigid-contact methods started a little off the full rub,
// which grow or decay as the eigenvalues say (and leave the full rub where
// it is unstable).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <memory>
#include <vector>

#include "rotor_rub_sim/core/contact_method.hpp"
#include "rotor_rub_sim/core/full_rub_stability.hpp"
#include "rotor_rub_sim/core/model.hpp"
#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"
#include "test_support.hpp"

using namespace rotor_rub;
using cd = std::complex<double>;

namespace {

// theta(t) - theta* of the linearisation, from theta - theta* = d at t = 0
// (the rest at equilibrium): V e^{Lambda t} V^-1 x0.
double linear_dtheta(const core::FullRubStability& s, double d, double t_s) {
  const int n = static_cast<int>(s.jacobian.rows()), th = n / 2 - 1;
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(s.jacobian);
  const Eigen::MatrixXcd v = eig.eigenvectors();
  Eigen::VectorXcd x0 = Eigen::VectorXcd::Zero(n);
  x0(th) = d;
  const Eigen::VectorXcd c = v.fullPivLu().solve(x0);
  cd out = 0.0;
  for (int k = 0; k < n; ++k) out += v(th, k) * c(k) * std::exp(eig.eigenvalues()(k) * t_s);
  return out.real();
}

struct Track {
  std::vector<double> t_s, dtheta_rad;
  bool stayed_in_contact = true;
};

// A rigid-contact method started on the full rub at w with the rotor turned
// by d on the bore (the stator and the velocities the full rub's), sampled
// every dt_s to end_s: theta - theta* in the turning frame.
Track perturbed_run(core::Method method, const core::ModelParameters& p, double w, const core::FullRubStability& rub,
                    double d, double dt_s, double end_s) {
  core::Scene s;
  s.model = p;
  s.solver.method = method;
  s.solver.integrator = method == core::Method::kPenalty ? core::Integrator::kRosenbrock4 : core::Integrator::kDop853;
  s.solver.rtol = 1e-10;
  s.solver.atol = 1e-14;
  s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = w;
  s.speed.acceleration_rad_per_s2 = 0.0;
  s.speed.max_speed_rad_per_s = std::max(s.speed.max_speed_rad_per_s, w);
  s.end_time_s = end_s;
  const core::SpeedProfile profile(s.speed);
  const std::unique_ptr<core::ContactMethod> m = core::make_contact_method(s);
  const double theta0 = std::arg(rub.station_m - rub.stator_m);
  const cd zr = rub.stator_m + (rub.station_m - rub.stator_m) * std::polar(1.0, d), vr = cd(0.0, w) * zr;
  const cd vs = cd(0.0, w) * rub.stator_m;
  core::Kinematics k = core::JeffcottModel(p).initial_kinematics(profile.at(0.0));
  k.rotor_pos = core::Vec2(zr.real(), zr.imag());
  k.rotor_vel = core::Vec2(vr.real(), vr.imag());
  if (p.stator_model == core::StatorModel::kElastic) {
    k.stator_pos = core::Vec2(rub.stator_m.real(), rub.stator_m.imag());
    k.stator_vel = core::Vec2(vs.real(), vs.imag());
  }
  m->start(0.0, k, profile.segment_at(0.0));
  std::vector<core::ContactEvent> events;
  m->change_model(0.0, p, events);  // in contact: decided as at a touchdown without closing speed
  Track out;
  const long samples = std::lround(end_s / dt_s);
  for (long j = 0; j <= samples; ++j) {
    const double t = std::min(end_s, static_cast<double>(j) * dt_s);
    while (m->step_end() < t) m->step(end_s, events);
    const core::Sample smp = m->sample(t);
    const cd gap = cd(smp.kin.rotor_pos.x() - smp.kin.stator_pos.x(), smp.kin.rotor_pos.y() - smp.kin.stator_pos.y());
    out.t_s.push_back(t);
    out.dtheta_rad.push_back(std::arg(gap * std::polar(1.0, -w * t - theta0)));
    out.stayed_in_contact = out.stayed_in_contact && (j == 0 || smp.in_contact);  // t = 0: the start's instant
  }
  return out;
}

}  // namespace

// The full rub is a rest point of the turning frame: its rates vanish there
// and the multiplier is the closed form's N (1e-9 of the forces' scale: the
// solve's rounding).
TEST(FullRubStability, TheFullRubIsARestPointOfTheTurningFrame) {
  struct Case {
    core::StatorModel stator;
    double f, w;
  };
  for (const Case& c : {Case{core::StatorModel::kRigid, 0.1, 300.0}, Case{core::StatorModel::kRigid, 0.3, 100.0},
                        Case{core::StatorModel::kElastic, 0.1, 120.0}, Case{core::StatorModel::kElastic, 0.1, 400.0}}) {
    const core::ModelParameters p = test::paper_model(c.stator, c.f);
    const auto branches = core::full_rub_stability(p, c.w);
    const auto closed = core::synchronous_full_rub(p, c.w);
    ASSERT_EQ(branches.size(), 2u) << c.w;
    for (std::size_t k = 0; k < 2; ++k) {
      double n = 0.0;
      const Eigen::VectorXd rates = core::full_rub_rates(core::turning_rotor(p), core::station_stator(p), p.clearance_m,
                                                         c.f, c.w, branches[k].state, &n);
      const double scale = p.rotor_mass_kg * p.eccentricity_m * c.w * c.w;  // the unbalance force [N]
      EXPECT_NEAR(n, closed[k].normal_force_N, 1e-9 * scale);
      EXPECT_NEAR(std::abs(branches[k].station_m - closed[k].rotor_m), 0.0, 1e-12);
      EXPECT_LT(rates.cwiseAbs().maxCoeff(), 1e-9 * c.w);
    }
  }
}

// Rigid stator: the linearisation's eigenvalues are the closed form's,
// m C l^2 + (c + 2 f m w) C l + |F| (cos phi - f sin phi) = 0, to the
// central differences' 1e-7; the upper branch (the larger N, where run-ups
// land) a stable focus or node, the lower a saddle, as cos phi - f sin phi
// says; at f = 0.3 and 120 rad/s both roots are real.
TEST(FullRubStability, RigidStatorIsTheClosedForm) {
  for (double f : {0.1, 0.3}) {
    for (double w : {100.0, 120.0, 300.0, 600.0}) {
      const core::ModelParameters p = test::paper_model(core::StatorModel::kRigid, f);
      const auto branches = core::full_rub_stability(p, w);
      if (f == 0.3 && w > 120.0) {
        EXPECT_TRUE(branches.empty()) << w;  // no full rub (docs/steady_response.md)
        continue;
      }
      ASSERT_EQ(branches.size(), 2u) << f << " " << w;
      for (std::size_t k = 0; k < 2; ++k) {
        const auto& b = branches[k];
        const auto closed = core::rigid_full_rub_eigenvalues(p, w, core::synchronous_full_rub(p, w)[k]);
        ASSERT_EQ(b.eigenvalues.size(), 2u);
        for (int j = 0; j < 2; ++j) {
          EXPECT_NEAR(std::abs(b.eigenvalues[j] - closed[j]), 0.0, 1e-7 * std::abs(closed[j])) << f << " " << w;
        }
        const double phi = std::arg(b.station_m) - p.unbalance_phase_rad;
        EXPECT_EQ(b.stable(), std::cos(phi) - f * std::sin(phi) > 0.0);
        EXPECT_EQ(b.stable(), k == 0) << "the upper branch stable, the lower a saddle: " << f << " " << w;
      }
    }
  }
}

// The runs: switching and iteration (dop853, rtol 1e-10) started on a branch
// with the rotor turned by d on the bore follow the linearisation's theta(t)
// to kLinear of the envelope d e^{max Re l t}: the nonlinear terms, O(d) =
// 1e-4 relative at most here, and the integration's error (measured: 4e-5):
// the rigid stator's stable upper branch at 300 rad/s (a focus, -31.6 +-
// 120.4i) and its saddle (+96.9), the elastic stator's upper branch at 120
// rad/s (stable: -3.2 +- 304.7i, its slowest mode, over 1 s) and at 300 rad/s, which flutters (+28.6 +- 114.9i: the run
// leaves the full rub, as the paper's run-up does above 2.79 s).
TEST(FullRubStability, RunsGrowAndDecayAtThePredictedRates) {
  struct Case {
    core::StatorModel stator;
    double w;
    std::size_t branch;
    double d, end_s;
  };
  for (const core::Method method : {core::Method::kSwitching, core::Method::kIteration}) {
    for (const Case& c :
         {Case{core::StatorModel::kRigid, 300.0, 0, 1e-4, 0.1}, Case{core::StatorModel::kRigid, 300.0, 1, 1e-6, 0.03},
          Case{core::StatorModel::kElastic, 120.0, 0, 1e-4, 1.0},
          Case{core::StatorModel::kElastic, 300.0, 0, 1e-6, 0.1}}) {
      const core::ModelParameters p = test::paper_model(c.stator, 0.1);
      const auto branches = core::full_rub_stability(p, c.w);
      ASSERT_GT(branches.size(), c.branch);
      const core::FullRubStability& b = branches[c.branch];
      SCOPED_TRACE(std::string(core::to_string(method)) + " " + core::to_string(c.stator) + " w " +
                   std::to_string(c.w) + " branch " + std::to_string(c.branch));
      const Track run = perturbed_run(method, p, c.w, b, c.d, 1e-3, c.end_s);
      const double growth = b.eigenvalues.front().real();
      double worst = 0.0;
      for (std::size_t j = 0; j < run.t_s.size(); ++j) {
        const double envelope = c.d * std::exp(std::max(growth, 0.0) * run.t_s[j]);
        worst = std::max(worst, std::abs(run.dtheta_rad[j] - linear_dtheta(b, c.d, run.t_s[j])) / envelope);
      }
      std::printf("%s %s w %g branch %zu: growth %.4g /s, run against the linearisation within %.2e of d e^{gt}\n",
                  core::to_string(method), core::to_string(c.stator), c.w, c.branch, growth, worst);
      constexpr double kLinear = 1e-3;
      EXPECT_LT(worst, kLinear) << "growth rate " << growth;
      EXPECT_TRUE(run.stayed_in_contact);
      if (growth > 0.0) {  // it grew as predicted: more than tenfold
        EXPECT_GT(std::abs(run.dtheta_rad.back()), 10.0 * c.d);
      } else {
        EXPECT_LT(std::abs(run.dtheta_rad.back()), 0.1 * c.d);
      }
    }
  }
}

// Where the full rub flutters, the run leaves it: the elastic stator at 300
// rad/s (f = 0.1), 1e-6 rad off the upper branch, lifts off within a second
// (the growth 28.6 /s takes 1e-6 to 1 in 0.48 s); the stable branch at 120
// rad/s holds through the same second.
TEST(FullRubStability, AnUnstableFullRubIsLeft) {
  const core::ModelParameters p = test::paper_model(core::StatorModel::kElastic, 0.1);
  const Track unstable =
      perturbed_run(core::Method::kSwitching, p, 300.0, core::full_rub_stability(p, 300.0)[0], 1e-6, 1e-3, 1.0);
  EXPECT_FALSE(unstable.stayed_in_contact);
  const Track stable =
      perturbed_run(core::Method::kSwitching, p, 120.0, core::full_rub_stability(p, 120.0)[0], 1e-6, 1e-3, 1.0);
  EXPECT_TRUE(stable.stayed_in_contact);
}

// The paper scene's full rub (elastic stator, f = 0.1) folds at 167.94 rad/s:
// its upper and lower branches meet there (an eigenvalue through 0) and no
// full rub exists up to 224 rad/s. Run up at 70 rad/s^2 and held: at 165
// rad/s (the stable branch: -2.5 +- 4.3i) the rotor stays in full rub to the
// end; at 170 rad/s, past the fold, it leaves it.
TEST(FullRubStability, PastItsFoldTheFullRubIsLeft) {
  const core::ModelParameters p = test::paper_scene().model;
  const auto at_fold = core::full_rub_stability(p, 167.9364);  // 4e-5 rad/s below the fold
  ASSERT_EQ(at_fold.size(), 2u);
  for (const auto& b : at_fold) {
    // One eigenvalue near 0, as 2.6 sqrt(distance): 0.015 /s here, 5 /s at 165 rad/s ...
    EXPECT_LT(std::abs(b.eigenvalues.front()), 0.05);
  }
  EXPECT_TRUE(core::full_rub_stability(p, 167.95).empty());  // ... and no full rub beyond
  for (const double w : {165.0, 170.0}) {
    core::Scene s = test::paper_scene();
    s.speed.target_speed_rad_per_s = w;
    s.end_time_s = 8.0;
    const test::Run run = test::run(s);
    ASSERT_FALSE(run.result.failure) << run.result.failure->message;
    EXPECT_EQ(run.out.samples.back().in_contact, w < 167.94) << w;
  }
}

// The flexible rotor: the isotropic seal rotor (test/data/rotors/
// isotropic_seal.yaml) in full rub on a rigid seal of 20 um at 300 rad/s,
// f = 0.1, settles onto the closed form with 4 and 8 planar modes and breaks
// into an intermittent rub with 12 and 16 (docs/rotor_theory.md, measured):
// the linearisation says why, a shaft mode at 2.40 kHz in the turning frame
// that friction makes flutter (+26.6 /s), which the models of 4 and 8 modes
// do not hold; from 12 modes on they give the full FE model's eigenvalue.
// The reduced models' rest points are the full model's projected, polished
// by Newton.
TEST(FullRubStability, TheSealRotorFluttersWithTwelveModesAndMore) {
  const core::FeRotor rotor = core::load_rotor_file(test::source_path("test/data/rotors/isotropic_seal.yaml"));
  const core::RotorMatrices m = core::assemble(rotor);
  const double w = 300.0, f = 0.1, c = 20e-6;
  std::complex<double> full_model;  // the full FE model's least stable eigenvalue
  for (const int modes : {0, 4, 8, 12, 16, 26}) {
    SCOPED_TRACE(modes);
    const core::ReducedRotor reduced = core::reduce_rotor(rotor, m, rotor.rub_station_node, modes > 0 ? modes : 1);
    const auto branches = core::full_rub_stability(m, rotor.rub_station_node, rotor.unbalances, core::StationStator{},
                                                   c, f, w, modes > 0 ? &reduced : nullptr);
    ASSERT_FALSE(branches.empty());
    const core::FullRubStability& upper = branches.front();
    const std::complex<double> l = upper.eigenvalues.front();
    std::printf(
        "%2d planar modes (0: the full FE model): N %.6g N, least stable %.4g %+.4gi /s (%.0f Hz in the "
        "turning frame)\n",
        modes, upper.normal_force_N, l.real(), l.imag(), std::abs(l.imag()) / (2.0 * M_PI));
    EXPECT_EQ(upper.stable(), modes == 4 || modes == 8);
    if (modes == 0) full_model = l;
    // From 12 planar modes the reduced models hold the full model's flutter:
    // its growth rate to 1 %, its frequency to 1e-4 (26: the full model in
    // other coordinates).
    if (modes >= 12) {
      EXPECT_NEAR(l.real(), full_model.real(), 1e-2 * full_model.real());
      EXPECT_NEAR(l.imag(), full_model.imag(), 1e-4 * std::abs(full_model.imag()));
    }
  }
}

// The penalty contact (k_c, c_c): its full rub is the rigid one with the bore
// moved out by N / k_c; its slow eigenvalues tend to the rigid contact's as
// k_c grows (the overlap's share, N / (k_c C), and the contact mode's
// coupling fall as 1 / k_c), and it adds the contact mode (sqrt(k_c / m)).
// The penalty method on dopri5 started on it with the rotor turned by 1e-4
// rad follows its linearisation as the rigid methods follow theirs.
TEST(FullRubStability, ThePenaltyContactTendsToTheRigidOne) {
  core::ModelParameters p = test::paper_model(core::StatorModel::kRigid, 0.1);
  const double w = 300.0;
  const auto rigid = core::full_rub_stability(p, w);
  double previous = 1.0;
  for (const double k_c : {1e7, 1e8, 1e9}) {
    p.contact_stiffness_N_per_m = k_c;
    const auto penalty = core::full_rub_stability(p, w, true);
    ASSERT_EQ(penalty.size(), 2u);
    const auto& upper = penalty.front();
    EXPECT_NEAR(upper.normal_force_N, rigid.front().normal_force_N, 1e-2 * rigid.front().normal_force_N);
    EXPECT_NEAR(std::abs(upper.station_m), p.clearance_m + upper.normal_force_N / k_c, 1e-12);
    // The slow pair: the two eigenvalues nearest the rigid focus.
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& l : upper.eigenvalues) nearest = std::min(nearest, std::abs(l - rigid.front().eigenvalues[0]));
    const double relative = nearest / std::abs(rigid.front().eigenvalues[0]);
    std::printf("penalty k_c %.0e: slow eigenvalue within %.2e of the rigid contact's; stable %d\n", k_c, relative,
                upper.stable());
    EXPECT_LT(relative, 0.5 * previous) << k_c;  // falls with k_c
    previous = relative;
    EXPECT_EQ(upper.stable(), rigid.front().stable());
    EXPECT_EQ(penalty[1].stable(), rigid[1].stable());
  }
}

// The penalty method (rosenbrock4, rtol 1e-10) started on the penalty
// contact's full rub (k_c 1e9, rigid stator, 300 rad/s) with the rotor turned
// by 1e-4 rad about the stator: the gap's angle follows the linearisation
// (the station's coordinates free, the contact mode among the eigenvalues)
// to kLinear of d, as the rigid methods do.
TEST(FullRubStability, ThePenaltyMethodFollowsItsLinearisation) {
  const core::ModelParameters p = test::paper_model(core::StatorModel::kRigid, 0.1);
  const double w = 300.0, d = 1e-4;
  const core::FullRubStability b = core::full_rub_stability(p, w, true).front();
  const Track run = perturbed_run(core::Method::kPenalty, p, w, b, d, 1e-3, 0.1);
  // The linear prediction: the station's coordinates turned by d about the
  // stator, rates 0; the gap's angle from its normal and tangent parts.
  const int n = static_cast<int>(b.jacobian.rows());
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(b.jacobian);
  const Eigen::MatrixXcd v = eig.eigenvectors();
  const cd gap = b.station_m - b.stator_m, moved = gap * std::polar(1.0, d) - gap;
  Eigen::VectorXcd x0 = Eigen::VectorXcd::Zero(n);
  x0(0) = moved.real();
  x0(1) = moved.imag();
  const Eigen::VectorXcd c = v.fullPivLu().solve(x0);
  double worst = 0.0;
  for (std::size_t j = 0; j < run.t_s.size(); ++j) {
    cd dx = 0.0, dy = 0.0;
    for (int k = 0; k < n; ++k) {
      const cd e = c(k) * std::exp(eig.eigenvalues()(k) * run.t_s[j]);
      dx += v(0, k) * e;
      dy += v(1, k) * e;
    }
    const cd dgap(dx.real(), dy.real());
    const double dtheta = std::imag(dgap / gap);  // the angle's first-order change
    worst = std::max(worst, std::abs(run.dtheta_rad[j] - dtheta) / d);
  }
  std::printf("penalty rigid w %g: run against the linearisation within %.2e of d\n", w, worst);
  constexpr double kLinear = 1e-3;  // as RunsGrowAndDecayAtThePredictedRates
  EXPECT_LT(worst, kLinear);
  EXPECT_TRUE(run.stayed_in_contact);
}

// The flexible rotor in the time domain: the seal rotor's full rub at 300
// rad/s, started through start_with_modes on the reduced model's branch
// (every coordinate at its rest point, turning at w: velocities w J v) with
// the station turned by d on the bore. With 12, 16 and 26 planar modes (26:
// the full FE model) it flutters (+26.6 /s): the switching method's run
// follows the linearisation (measured: to 6e-6 of d e^{gt}, over 0.2 s with
// 26 modes, a growth of 200); with 8 it holds (-2.2 /s) and follows it too.
// kLinear as for the Jeffcott.
TEST(FullRubStability, TheSealRotorsRunsFollowTheLinearisation) {
  const std::string file = test::source_path("test/data/rotors/isotropic_seal.yaml");
  const core::FeRotor rotor = core::load_rotor_file(file);
  const core::RotorMatrices m = core::assemble(rotor);
  const double w = 300.0, f = 0.1, c = 20e-6, d = 1e-6;
  for (const auto& [modes, end_s] : {std::pair<long, double>{26, 0.2}, {12, 0.04}, {16, 0.04}, {8, 0.02}}) {
    SCOPED_TRACE(modes);
    core::Scene s;
    s.rotor.file = file;
    s.rotor.planar_modes = modes;
    s.model.stator_model = core::StatorModel::kRigid;
    s.model.clearance_m = c;
    s.model.friction_coefficient = f;
    s.solver.method = core::Method::kSwitching;
    s.solver.integrator = core::Integrator::kDop853;
    s.solver.rtol = 1e-10;
    s.solver.atol = 1e-15;
    s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = w;
    s.speed.acceleration_rad_per_s2 = 0.0;
    s.end_time_s = end_s;
    core::load_rotor(s);
    const core::SpeedProfile profile(s.speed);
    const std::unique_ptr<core::ContactMethod> method = core::make_contact_method(s);
    const core::ReducedRotor& reduced = method->flexible_rotor()->rotor();
    const core::FullRubStability b =
        core::full_rub_stability(m, rotor.rub_station_node, rotor.unbalances, core::StationStator{}, c, f, w, &reduced)
            .front();
    EXPECT_EQ(b.stable(), modes == 8);
    // The reduced coordinates at the rest point, the station turned by d.
    const core::TurningRotor turning = core::turning_rotor(reduced, m, rotor.unbalances);
    const int n = static_cast<int>(reduced.matrices.M.rows()), nq = n - 1;
    Eigen::VectorXd v(n);
    const double theta0 = std::arg(b.station_m);
    v(0) = c * std::cos(theta0 + d);
    v(1) = c * std::sin(theta0 + d);
    v.tail(n - 2) = b.state.head(n - 2);
    const Eigen::VectorXd vd = w * (turning.turn * v);
    core::Kinematics k = core::JeffcottModel(s.model).initial_kinematics(profile.at(0.0));
    k.rotor_pos = core::Vec2(v(0), v(1));
    k.rotor_vel = core::Vec2(vd(0), vd(1));
    core::ModalState modal(2 * (n - 2));
    modal.head(n - 2) = v.tail(n - 2);
    modal.tail(n - 2) = vd.tail(n - 2);
    method->start_with_modes(0.0, k, profile.segment_at(0.0), modal);
    std::vector<core::ContactEvent> events;
    method->change_model(0.0, s.model, events);
    // The linearisation's theta(t) from theta - theta* = d (coordinate nq - 1).
    Eigen::VectorXd x0 = Eigen::VectorXd::Zero(2 * nq);
    x0(nq - 1) = d;
    const double growth = b.eigenvalues.front().real();
    double worst = 0.0;
    bool in_contact = true;
    for (int j = 1; j <= 40; ++j) {
      const double t = end_s * j / 40.0;
      while (method->step_end() < t) method->step(end_s, events);
      const core::Sample smp = method->sample(t);
      in_contact = in_contact && smp.in_contact;
      const double run = std::arg(cd(smp.kin.rotor_pos.x(), smp.kin.rotor_pos.y()) * std::polar(1.0, -w * t - theta0));
      const double lin = core::linear_response(b.jacobian, x0, t)(nq - 1);
      worst = std::max(worst, std::abs(run - lin) / (d * std::exp(std::max(growth, 0.0) * t)));
    }
    std::printf("seal rotor, %ld planar modes: growth %.4g /s, run against the linearisation within %.2e of d e^{gt}\n",
                modes, growth, worst);
    constexpr double kLinear = 1e-3;  // as RunsGrowAndDecayAtThePredictedRates
    EXPECT_LT(worst, kLinear);
    EXPECT_TRUE(in_contact);
  }
}

// start_with_modes refuses a modal block of the wrong size, naming both
// sizes (4 planar modes: 6 modal coordinates, a block of 12); a Jeffcott
// method has no modes (a logic error to call it).
TEST(FullRubStability, StartWithModesChecksTheBlock) {
  core::Scene s;
  s.rotor.file = test::source_path("test/data/rotors/isotropic_seal.yaml");
  s.rotor.planar_modes = 4;
  core::load_rotor(s);
  const core::SpeedProfile profile(s.speed);
  const core::Kinematics k = core::JeffcottModel(s.model).initial_kinematics(profile.at(0.0));
  const std::unique_ptr<core::ContactMethod> flexible = core::make_contact_method(s);
  try {
    flexible->start_with_modes(0.0, k, profile.segment_at(0.0), core::ModalState::Zero(4));
    ADD_FAILURE() << "a block of 4 entries accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("a modal block of 4 entries; accepted: 12"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(flexible->start_with_modes(0.0, k, profile.segment_at(0.0), core::ModalState::Zero(12)));
  const std::unique_ptr<core::ContactMethod> jeffcott = core::make_contact_method(core::Scene());
  EXPECT_THROW(jeffcott->start_with_modes(0.0, k, profile.segment_at(0.0), core::ModalState()), std::logic_error);
}
