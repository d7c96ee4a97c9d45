// Branches of periodic orbits in the speed (orbit_continuation.hpp) on the
// paper's rotor lying horizontal on a rigid stator (its sag 1.64 mm of the
// 2 mm clearance, e = 0.5): one impact per revolution from 53 to 65 rad/s.
// The bifurcations located along the branch are checked on the orbits
// themselves (a multiplier at -1, a pair on the unit circle), and the
// switching method's runs are checked against the branches: the unstable
// orbit's disturbance grows at its largest multiplier, and a run settles on
// the doubled orbit that branch switching found.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/full_rub_stability.hpp"
#include "rotor_rub_sim/core/orbit_continuation.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

core::ModelParameters horizontal() {
  core::ModelParameters p = test::paper_scene().model;
  p.stator_model = core::StatorModel::kRigid;
  p.gravity_m_per_s2 = 9.81;
  p.restitution = 0.5;
  return p;
}

core::ContinuationSettings range(bool up) {
  core::ContinuationSettings s;
  s.min_speed_rad_per_s = 40.0;
  s.max_speed_rad_per_s = 80.0;
  s.increasing_speed = up;
  return s;
}

const core::OrbitBifurcation* first(const core::OrbitBranch& b, core::OrbitBifurcationKind kind) {
  for (const auto& bif : b.bifurcations) {
    if (bif.kind == kind) return &bif;
  }
  return nullptr;
}

// The bifurcations' regula falsi stops on 1e-8 of a step (at most 0.05 in
// the scaled unknowns); the multipliers move by about 20 per rad/s there.
constexpr double kLocated = 1e-5;

struct Branches {
  core::PeriodicOrbit start;
  core::OrbitBranch down, up;
};
const Branches& branches() {
  static const Branches b = [] {
    Branches out;
    const core::ModelParameters p = horizontal();
    out.start = core::find_periodic_orbit(p, 60.0, core::settled_state(p, 60.0, 100));
    out.down = core::continue_orbit(p, out.start, range(false));
    out.up = core::continue_orbit(p, out.start, range(true));
    return out;
  }();
  return b;
}

}  // namespace

// Down in speed the impacting orbit doubles its period at 53.09 rad/s, where
// a real multiplier passes -1 (the orbit found again there by
// find_periodic_orbit has it to kLocated), then its impact slows to a
// graze: the trace ends where the events change, its multipliers growing as
// the impact velocity falls (the grazing's square-root singularity).
TEST(OrbitContinuation, DownInSpeedTheOrbitDoublesThenGrazes) {
  const Branches& b = branches();
  const core::OrbitBifurcation* pd = first(b.down, core::OrbitBifurcationKind::kPeriodDoubling);
  ASSERT_NE(pd, nullptr);
  std::printf("period doubling at %.9f rad/s; the trace ends: %s\n", pd->speed_rad_per_s, b.down.end.c_str());
  EXPECT_GT(pd->speed_rad_per_s, 53.0);
  EXPECT_LT(pd->speed_rad_per_s, 53.2);
  const core::PeriodicOrbit again = core::find_periodic_orbit(horizontal(), pd->speed_rad_per_s, pd->orbit.state);
  for (const core::PeriodicOrbit* o : {&pd->orbit, &again}) {
    double nearest = INFINITY;
    for (const auto& mu : o->multipliers) nearest = std::min(nearest, std::abs(mu + 1.0));
    EXPECT_LT(nearest, kLocated);
  }
  EXPECT_NE(b.down.end.find("events change"), std::string::npos) << b.down.end;
  const core::PeriodicOrbit& last = b.down.points.back();
  EXPECT_LT(last.speed_rad_per_s, pd->speed_rad_per_s);
  EXPECT_LT(last.slowest_impact, 0.1 * b.start.slowest_impact);
  EXPECT_GT(std::abs(last.multipliers.front()), 10.0);
  for (const auto& pt : b.down.points) EXPECT_EQ(pt.events.size(), 1u);
}

// Up in speed a complex pair of multipliers leaves the unit circle (a
// Neimark-Sacker point) near 64.9 rad/s.
TEST(OrbitContinuation, UpInSpeedAPairCrossesTheUnitCircle) {
  const Branches& b = branches();
  const core::OrbitBifurcation* ns = first(b.up, core::OrbitBifurcationKind::kNeimarkSacker);
  ASSERT_NE(ns, nullptr) << b.up.end;
  std::printf("Neimark-Sacker at %.9f rad/s; the trace ends: %s\n", ns->speed_rad_per_s, b.up.end.c_str());
  double nearest = INFINITY;
  for (const auto& mu : ns->orbit.multipliers) {
    if (std::abs(mu.imag()) > 1e-6) nearest = std::min(nearest, std::abs(std::abs(mu) - 1.0));
  }
  EXPECT_LT(nearest, kLocated);
  EXPECT_TRUE(b.start.stable());
  for (const auto& pt : b.up.points) EXPECT_EQ(pt.stable(), pt.speed_rad_per_s < ns->speed_rad_per_s);
}

// Between the doubling and the graze the single orbit is unstable: the
// switching method started 1e-9 of C off it leaves it at its largest
// multiplier's rate, to kRate (the runs' rtol 1e-10 against a disturbance
// of 1e-9 to 1e-6: 1e-4 relative, over ten periods), and settles on the
// doubled orbit that branch switching found there, to kSettled (the orbit's
// slowest multiplier after the run's periods).
TEST(OrbitContinuation, RunsLeaveTheUnstableOrbitAndSettleOnTheDoubledOne) {
  constexpr double kRate = 0.02;
  constexpr double kSettled = 1e-6;
  const core::ModelParameters p = horizontal();
  const Branches& b = branches();
  const core::OrbitBifurcation* pd = first(b.down, core::OrbitBifurcationKind::kPeriodDoubling);
  ASSERT_NE(pd, nullptr);
  const core::OrbitBranch doubled = core::continue_period_doubled(p, *pd, range(false));
  ASSERT_GE(doubled.points.size(), 3u) << doubled.end;
  // A stable doubled orbit a little below the doubling.
  const core::PeriodicOrbit* two = nullptr;
  for (const auto& pt : doubled.points) {
    if (pt.stable() && pt.speed_rad_per_s < pd->speed_rad_per_s - 0.005) {
      two = &pt;
      break;
    }
  }
  ASSERT_NE(two, nullptr) << doubled.end;
  const double w = two->speed_rad_per_s, period = 2.0 * M_PI / w;
  std::printf("the doubled orbit at %.6f rad/s: |mu| max %.4f, %zu events\n", w, std::abs(two->multipliers.front()),
              two->events.size());
  EXPECT_EQ(two->periods, 2);
  EXPECT_EQ(two->events.size(), 2u);
  ASSERT_EQ(two->keyphasor_states.size(), 2u);
  EXPECT_GT(test::scaled_norm(two->keyphasor_states[0] - two->keyphasor_states[1], p, w), 1e-4);
  const core::PeriodicOrbit one = core::find_periodic_orbit(p, w, pd->orbit.state);
  ASSERT_FALSE(one.stable());
  const double growth = std::abs(one.multipliers.front());
  Eigen::VectorXd start = one.state;
  start(0) += 1e-9 * p.clearance_m;
  std::vector<double> times;
  for (int k = 0; k <= 400; ++k) times.push_back(k * period);
  const std::vector<Eigen::VectorXd> run = test::method_states(core::Method::kSwitching, p, w, start, times);
  const double d5 = test::scaled_norm(run[5] - one.state, p, w), d15 = test::scaled_norm(run[15] - one.state, p, w);
  const double rate = std::pow(d15 / d5, 0.1);
  std::printf("the run leaves the single orbit at %.5f per period; its largest multiplier %.5f\n", rate, growth);
  EXPECT_NEAR(rate / growth, 1.0, kRate);
  const Eigen::VectorXd& a = run[399];
  const Eigen::VectorXd& c = run[400];
  const double settled = std::min(std::max(test::scaled_norm(a - two->keyphasor_states[0], p, w),
                                           test::scaled_norm(c - two->keyphasor_states[1], p, w)),
                                  std::max(test::scaled_norm(a - two->keyphasor_states[1], p, w),
                                           test::scaled_norm(c - two->keyphasor_states[0], p, w)));
  std::printf("after 400 periods the run is %.2e of C from the doubled orbit\n", settled);
  EXPECT_LT(settled, kSettled);
  // The doubled orbit doubles again close below (a cascade): there the
  // run repeats every 4 periods, not every 2.
  const core::OrbitBifurcation* pd2 = first(doubled, core::OrbitBifurcationKind::kPeriodDoubling);
  ASSERT_NE(pd2, nullptr) << doubled.end;
  std::printf("the doubled orbit doubles at %.9f rad/s\n", pd2->speed_rad_per_s);
  EXPECT_LT(pd2->speed_rad_per_s, w);
  const double w4 = pd2->speed_rad_per_s - 0.002, period4 = 2.0 * M_PI / w4;
  Eigen::VectorXd start4 = core::find_periodic_orbit(p, w4, pd->orbit.state).state;
  start4(0) += 1e-6 * p.clearance_m;
  std::vector<double> times4;
  for (int k = 2990; k <= 3000; ++k) times4.push_back(k * period4);
  times4.insert(times4.begin(), 0.0);
  const std::vector<Eigen::VectorXd> run4 = test::method_states(core::Method::kSwitching, p, w4, start4, times4);
  const double every4 = test::scaled_norm(run4[10] - run4[6], p, w4),
               every2 = test::scaled_norm(run4[10] - run4[8], p, w4);
  std::printf("at %.4f rad/s the run repeats every 4 periods to %.2e of C, every 2 to %.2e\n", w4, every4, every2);
  EXPECT_LT(every4, kSettled);
  EXPECT_GT(every2, 100.0 * kSettled);
}

// With less sag (g = 7 m/s^2) the branch from 90 rad/s down loses and
// regains its stability at two Neimark-Sacker points and turns back at a
// fold at 70.11 rad/s, where a real multiplier passes +1: above the fold two
// orbits (the stable one traced before it, a saddle after it), below it
// none; a run started 1e-9 of C off the saddle leaves it at its largest
// multiplier's rate, to kRate (the run's rtol 1e-10 against a disturbance
// of 1e-8 to 2e-5 of C).
TEST(OrbitContinuation, TheBranchTurnsBackAtAFold) {
  constexpr double kRate = 0.02;
  core::ModelParameters p = horizontal();
  p.gravity_m_per_s2 = 7.0;
  const core::PeriodicOrbit start = core::find_periodic_orbit(p, 90.0, core::settled_state(p, 90.0, 200));
  core::ContinuationSettings settings = range(false);
  settings.max_speed_rad_per_s = 100.0;
  const core::OrbitBranch down = core::continue_orbit(p, start, settings);
  const core::OrbitBifurcation* fold = first(down, core::OrbitBifurcationKind::kFold);
  ASSERT_NE(fold, nullptr) << down.end;
  std::printf("fold at %.9f rad/s; the trace ends: %s\n", fold->speed_rad_per_s, down.end.c_str());
  double nearest = INFINITY;
  for (const auto& mu : fold->orbit.multipliers) nearest = std::min(nearest, std::abs(mu - 1.0));
  EXPECT_LT(nearest, kLocated);
  // The points on either side of the fold in the order traced.
  std::size_t k = 0;
  while (k + 1 < down.points.size() && down.points[k + 1].speed_rad_per_s < down.points[k].speed_rad_per_s) ++k;
  ASSERT_LT(k + 1, down.points.size()) << "the trace does not turn back";
  EXPECT_NEAR(down.points[k].speed_rad_per_s, fold->speed_rad_per_s, 0.1);
  const double above = fold->speed_rad_per_s + 0.05;
  const core::PeriodicOrbit node = core::find_periodic_orbit(p, above, down.points[k - 1].state);
  const core::PeriodicOrbit saddle = core::find_periodic_orbit(p, above, down.points[k + 1].state);
  EXPECT_GT(test::scaled_norm(node.state - saddle.state, p, above), 1e-4);
  EXPECT_TRUE(node.stable());
  ASSERT_FALSE(saddle.stable());
  EXPECT_LT(std::abs(saddle.multipliers.front().imag()), 1e-9);  // a real multiplier past +1
  EXPECT_GT(saddle.multipliers.front().real(), 1.0);
  EXPECT_THROW(core::find_periodic_orbit(p, fold->speed_rad_per_s - 0.05, fold->orbit.state), core::OrbitError);
  Eigen::VectorXd off = saddle.state;
  off(0) += 1e-9 * p.clearance_m;
  const double period = 2.0 * M_PI / above;
  std::vector<double> times;
  for (int j = 0; j <= 35; ++j) times.push_back(j * period);
  const auto run = test::method_states(core::Method::kSwitching, p, above, off, times);
  // From the 20th period: the next multipliers, a complex pair of modulus
  // 0.94, have died against the saddle's by then (a factor 1e-3).
  const double rate = std::pow(
      test::scaled_norm(run[35] - saddle.state, p, above) / test::scaled_norm(run[20] - saddle.state, p, above),
      1.0 / 15.0);
  std::printf("the run leaves the saddle at %.5f per period; its largest multiplier %.5f\n", rate,
              saddle.multipliers.front().real());
  EXPECT_NEAR(rate / saddle.multipliers.front().real(), 1.0, kRate);
}

// Plastic (e = 0) at 100 rad/s the orbit lifts off, flies, hits the bore
// and touches down into a contact that holds through the section: its
// multipliers there are the bore's tangent space's (two). Taken again at a
// section in free flight (continue_orbit does) it has four, two of them 0
// (the touchdown's), and the others are the same: the multipliers do not
// depend on the section, to kSection (the contact field's differences).
// The doubled orbit traced up from 53.07 rad/s turns back where it meets
// the single one, at the doubling: the trace ends there, no fold.
TEST(OrbitContinuation, SectionsInContactAndDoubledBranchesMeetingTheSingle) {
  constexpr double kSection = 1e-8;
  core::ModelParameters p = horizontal();
  p.restitution = 0.0;
  const core::PeriodicOrbit o = core::find_periodic_orbit(p, 100.0, core::settled_state(p, 100.0, 200));
  ASSERT_TRUE(o.starts_in_contact);
  ASSERT_FALSE(o.events.empty());
  ASSERT_EQ(o.multipliers.size(), 2u);
  core::ContinuationSettings up = range(true);
  up.max_speed_rad_per_s = 110.0;
  const core::OrbitBranch b = core::continue_orbit(p, o, up);
  ASSERT_GE(b.points.size(), 2u) << b.end;
  const core::PeriodicOrbit& moved = b.points.front();
  EXPECT_FALSE(moved.starts_in_contact);
  ASSERT_EQ(moved.multipliers.size(), 4u);
  EXPECT_LT(std::abs(moved.multipliers[2]), kSection);
  EXPECT_LT(std::abs(moved.multipliers[3]), kSection);
  for (int j = 0; j < 2; ++j) EXPECT_LT(std::abs(moved.multipliers[j] - o.multipliers[j]), kSection) << j;
  std::printf("the orbit at 100 rad/s: its multipliers %.9f, %.9f on the bore; the branch ends: %s\n",
              std::abs(o.multipliers[0]), std::abs(o.multipliers[1]), b.end.c_str());

  const core::ModelParameters h = horizontal();
  core::OrbitSettings two;
  two.periods = 2;
  const core::PeriodicOrbit doubled = core::find_periodic_orbit(h, 53.07, core::settled_state(h, 53.07, 400), two);
  ASSERT_TRUE(doubled.stable());
  const core::OrbitBranch toward = core::continue_orbit(h, doubled, range(true), two);
  std::printf("the doubled branch up from 53.07 rad/s ends: %s\n", toward.end.c_str());
  EXPECT_NE(toward.end.find("meets the orbit of half its period at 53.0920"), std::string::npos) << toward.end;
  EXPECT_EQ(first(toward, core::OrbitBifurcationKind::kFold), nullptr);
  for (const auto& pt : toward.points) EXPECT_LT(pt.speed_rad_per_s, 53.0921);
}

// Any number of the model may be the parameter, at a constant speed: in
// the gravity at 60 rad/s the branch doubles at 8.8466 m/s^2, where the
// orbit found again at that gravity has a multiplier at -1 (kLocated).
TEST(OrbitContinuation, ABranchInAKeyOfTheModel) {
  const core::ModelParameters p = horizontal();
  const core::PeriodicOrbit start = core::find_periodic_orbit(p, 60.0, core::settled_state(p, 60.0, 100));
  core::ContinuationParameter gravity;
  gravity.name = "gravity_m_per_s2";
  gravity.unit = "";
  gravity.model = [&p](double g) {
    core::ModelParameters q = p;
    q.gravity_m_per_s2 = g;
    return q;
  };
  core::ContinuationSettings down;
  down.min_speed_rad_per_s = 5.0;  // (the settings' bounds are the parameter's, here m/s^2)
  down.max_speed_rad_per_s = 15.0;
  down.increasing_speed = false;
  const core::OrbitBranch b = core::continue_orbit(p, start, down, {}, gravity, p.gravity_m_per_s2);
  const core::OrbitBifurcation* pd = first(b, core::OrbitBifurcationKind::kPeriodDoubling);
  ASSERT_NE(pd, nullptr) << b.end;
  std::printf("in the gravity: a period doubling at %.9f m/s^2; the trace ends: %s\n", pd->parameter, b.end.c_str());
  EXPECT_DOUBLE_EQ(pd->speed_rad_per_s, 60.0);
  for (const auto& pt : b.points) EXPECT_DOUBLE_EQ(pt.speed_rad_per_s, 60.0);
  const core::PeriodicOrbit again = core::find_periodic_orbit(gravity.model(pd->parameter), 60.0, pd->orbit.state);
  double nearest = INFINITY;
  for (const auto& mu : again.multipliers) nearest = std::min(nearest, std::abs(mu + 1.0));
  EXPECT_LT(nearest, kLocated);
}

TEST(OrbitContinuation, BadInputIsAClearError) {
  const core::ModelParameters p = horizontal();
  const Branches& b = branches();
  core::ContinuationSettings empty = range(true);
  empty.max_speed_rad_per_s = empty.min_speed_rad_per_s;
  EXPECT_THROW(core::continue_orbit(p, b.start, empty), std::invalid_argument);
  core::ContinuationSettings above = range(true);
  above.min_speed_rad_per_s = 70.0;
  EXPECT_THROW(core::continue_orbit(p, b.start, above), std::invalid_argument);
  core::OrbitBifurcation not_pd;
  not_pd.kind = core::OrbitBifurcationKind::kNeimarkSacker;
  not_pd.orbit = b.start;
  not_pd.speed_rad_per_s = 60.0;
  EXPECT_THROW(core::continue_period_doubled(p, not_pd, range(true)), std::invalid_argument);
}

// The full rub never leaves the bore (no events): traced on the bore's
// tangent space, each point is full_rub_stability's steady state at its
// speed (the turning frame's equilibrium at spin angle 0) to kFixedPoint of
// C (the Newton tolerance 1e-9 over 1 - |mu|, here at least 0.4; measured
// 1.2e-10), and as stable.
TEST(OrbitContinuation, TheFullRubsBranchIsTheTurningFramesEquilibria) {
  constexpr double kFixedPoint = 1e-8;
  core::ModelParameters rub = horizontal();
  rub.gravity_m_per_s2 = 0.0;
  const auto branches = core::full_rub_stability(rub, 300.0);
  ASSERT_FALSE(branches.empty());
  Eigen::VectorXd guess(4);
  const std::complex<double> z = branches.front().station_m, v = std::complex<double>(0.0, 300.0) * z;
  guess << z.real(), z.imag(), v.real(), v.imag();
  const core::PeriodicOrbit full_rub = core::find_periodic_orbit(rub, 300.0, guess);
  ASSERT_TRUE(full_rub.starts_in_contact && full_rub.events.empty());
  core::ContinuationSettings around = range(true);
  around.min_speed_rad_per_s = 250.0;
  around.max_speed_rad_per_s = 350.0;
  const core::OrbitBranch up = core::continue_orbit(rub, full_rub, around);
  std::printf("the full rub's branch up from 300 rad/s: %zu points, it ends: %s\n", up.points.size(), up.end.c_str());
  ASSERT_GT(up.points.size(), 3u);
  double worst = 0.0;
  for (const core::PeriodicOrbit& o : up.points) {
    double nearest = INFINITY;
    bool stable = false;
    for (const core::FullRubStability& f : core::full_rub_stability(rub, o.speed_rad_per_s)) {
      const double off = std::abs(std::complex<double>(o.state(0), o.state(1)) - f.station_m) / rub.clearance_m;
      if (off < nearest) {
        nearest = off;
        stable = f.stable();
      }
    }
    EXPECT_LT(nearest, kFixedPoint) << o.speed_rad_per_s;
    EXPECT_EQ(o.stable(), stable) << o.speed_rad_per_s;
    worst = std::max(worst, nearest);
  }
  std::printf("the full rub's branch against the turning frame's equilibria: %.2e of C at worst\n", worst);
}

// An orbit on the bore throughout, sticking and slipping twice a revolution
// (test_periodic_orbit.cpp's thin shaft: R_r = C, f = 1, plastic, 110
// rad/s), traced on the bore's tangent space: down in speed it doubles its
// period at 107.505 rad/s (the orbit found again there has a multiplier at
// -1 to kLocated), and a switching-method run between that doubling and the
// doubled orbit's own settles on an orbit of two periods, to kSettled of C
// (the run's rtol 1e-10 over 400 periods); up in speed the trace ends where
// a slip comes to rest tangentially (a stick phase is born or dies there).
TEST(OrbitContinuation, AStickSlipBranchOnTheBore) {
  constexpr double kSettled = 1e-8;
  core::ModelParameters p = horizontal();
  p.restitution = 0.0;
  p.rotor_radius_m = p.clearance_m;
  p.friction_coefficient = 1.0;
  const core::PeriodicOrbit start = core::find_periodic_orbit(p, 110.0, core::settled_state(p, 110.0, 300));
  ASSERT_TRUE(start.starts_in_contact);
  core::ContinuationSettings settings = range(false);
  settings.min_speed_rad_per_s = 100.0;
  settings.max_speed_rad_per_s = 120.0;
  const core::OrbitBranch down = core::continue_orbit(p, start, settings);
  settings.increasing_speed = true;
  const core::OrbitBranch up = core::continue_orbit(p, start, settings);
  for (const core::OrbitBranch* b : {&down, &up}) {
    for (const auto& pt : b->points) {
      EXPECT_TRUE(pt.starts_in_contact);
      EXPECT_EQ(pt.events.size(), start.events.size());
    }
  }
  const core::OrbitBifurcation* pd = first(down, core::OrbitBifurcationKind::kPeriodDoubling);
  ASSERT_NE(pd, nullptr) << down.end;
  std::printf("the stick-slip orbit doubles at %.9f rad/s; down it ends: %s; up: %s\n", pd->speed_rad_per_s,
              down.end.c_str(), up.end.c_str());
  EXPECT_GT(pd->speed_rad_per_s, 107.4);
  EXPECT_LT(pd->speed_rad_per_s, 107.6);
  core::OrbitSettings at_section;
  at_section.section_angle_rad = pd->orbit.section_angle_rad;
  const core::PeriodicOrbit again = core::find_periodic_orbit(p, pd->speed_rad_per_s, pd->orbit.state, at_section);
  double nearest = INFINITY;
  for (const auto& mu : again.multipliers) nearest = std::min(nearest, std::abs(mu + 1.0));
  EXPECT_LT(nearest, kLocated);
  EXPECT_NE(up.end.find("comes to rest tangentially"), std::string::npos) << up.end;
  // Between the doubling and the doubled orbit's own (107.43 rad/s).
  const double w = 107.47, period = 2.0 * M_PI / w;
  const core::OrbitBranch doubled = core::continue_period_doubled(p, *pd, settings);
  const core::OrbitBifurcation* pd2 = first(doubled, core::OrbitBifurcationKind::kPeriodDoubling);
  ASSERT_NE(pd2, nullptr) << doubled.end;
  std::printf("the doubled stick-slip orbit doubles at %.9f rad/s\n", pd2->speed_rad_per_s);
  EXPECT_LT(pd2->speed_rad_per_s, w);
  EXPECT_GT(pd2->speed_rad_per_s, 107.4);
  std::vector<double> times;
  for (int k = 397; k <= 400; ++k) times.push_back(k * period);
  const std::vector<Eigen::VectorXd> run =
      test::method_states(core::Method::kSwitching, p, w, core::settled_state(p, w, 0), times);
  const double every2 = test::scaled_norm(run[3] - run[1], p, w), every1 = test::scaled_norm(run[3] - run[2], p, w);
  std::printf("at %.2f rad/s the run repeats every 2 periods to %.2e of C, every period to %.2e\n", w, every2, every1);
  EXPECT_LT(every2, kSettled);
  EXPECT_GT(every1, 100.0 * kSettled);
}

// The hysteresis band of the paper's scene (elastic stator, f = 0.1): at 160
// rad/s the full rub (found from the turning frame's equilibrium, as a
// run-up would leave it) traced up in speed on the bore's tangent space turns
// back at a fold where full_rub_continuation's turning-frame branch does,
// to kFold (each located by regula falsi to 1e-8 of a step of 0.05 in its
// scaled arclength, where the speed is stationary: they agree to 9 digits).
TEST(OrbitContinuation, TheFullRubsFoldByShootingIsTheTurningFrames) {
  constexpr double kFold = 1e-6;
  const core::ModelParameters p = test::paper_scene().model;
  const double w = 160.0;
  const auto rubs = core::full_rub_stability(p, w);
  ASSERT_FALSE(rubs.empty());
  const std::complex<double> i_w(0.0, w), z = rubs.front().station_m, zs = rubs.front().stator_m;
  Eigen::VectorXd guess(8);
  guess << z.real(), z.imag(), zs.real(), zs.imag(), (i_w * z).real(), (i_w * z).imag(), (i_w * zs).real(),
      (i_w * zs).imag();
  const core::PeriodicOrbit start = core::find_periodic_orbit(p, w, guess);
  ASSERT_TRUE(start.starts_in_contact && start.events.empty());
  core::ContinuationSettings settings = range(true);
  settings.min_speed_rad_per_s = 150.0;
  settings.max_speed_rad_per_s = 200.0;
  const core::OrbitBranch up = core::continue_orbit(p, start, settings);
  const core::OrbitBifurcation* fold = first(up, core::OrbitBifurcationKind::kFold);
  ASSERT_NE(fold, nullptr) << up.end;
  const core::FullRubBranch turning =
      core::continue_full_rub(core::turning_rotor(p), core::station_stator(p), p.clearance_m, p.friction_coefficient,
                              rubs.front(), w, settings);
  ASSERT_FALSE(turning.folds_rad_per_s.empty()) << turning.end;
  std::printf("the full rub's fold by shooting %.9f rad/s, in the turning frame %.9f rad/s\n", fold->speed_rad_per_s,
              turning.folds_rad_per_s.front());
  EXPECT_NEAR(fold->speed_rad_per_s, turning.folds_rad_per_s.front(), kFold);
}
