// The bifurcation classes (response_class.hpp) on series whose nature is known:
// periodic cycles, a rotation by an irrational angle (quasi-periodic), the
// logistic map at r = 4 (chaotic), forward and backward circular whirl.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <stdexcept>
#include <string>

#include "rotor_rub_sim/core/response_class.hpp"

using namespace rotor_rub;
using core::Vec2;

namespace {

constexpr double kClearance_m = 2e-3;

core::Sample sample_at(double t, const Vec2& rel, double whirl_rad_per_s, bool contact) {
  core::Sample s;
  s.t_s = t;
  s.kin.rotor_pos = rel;
  s.kin.rotor_vel = whirl_rad_per_s * Vec2(-rel.y(), rel.x());  // circular whirl at that rate
  s.in_contact = contact;
  s.normal_force_N = contact ? 1.0 : 0.0;
  return s;
}

core::ResponseWindow window_of(const std::vector<Vec2>& points, double whirl = 1.0, bool contact = false) {
  core::ResponseWindow w;
  for (std::size_t j = 0; j < points.size(); ++j) {
    const core::Sample s = sample_at(double(j), points[j], whirl, contact);
    w.add_point(s);
    w.add_sample(s);
  }
  return w;
}

}  // namespace

TEST(ResponseClass, PeriodicCyclesAreFoundWithTheirPeriod) {
  for (int n : {1, 2, 3, 5, 8}) {
    std::vector<Vec2> pts;
    for (int j = 0; j < 256; ++j) {
      const double a = 2 * M_PI * (j % n) / n;
      // Within the tolerance of the cycle: integration noise of 1e-9 m.
      pts.push_back(1e-3 * Vec2(std::cos(a), std::sin(a)) + 1e-9 * Vec2(std::sin(j * 1.3), 0.0));
    }
    const auto c = core::classify_response(window_of(pts), kClearance_m);
    EXPECT_EQ(c.motion, core::Motion::kPeriodic) << n;
    EXPECT_EQ(c.period, n);
    EXPECT_EQ(c.distinct_points, n);
    EXPECT_EQ(c.response, core::ResponseClass::kNoContact);
  }
}

TEST(ResponseClass, IrrationalRotationIsQuasiPeriodic) {
  const double golden = (std::sqrt(5.0) - 1.0) / 2.0;
  std::vector<Vec2> pts;
  for (int j = 0; j < 512; ++j) {
    const double a = 2 * M_PI * golden * j;
    // An invariant circle, not centred: |p| varies quasi-periodically.
    pts.push_back(Vec2(0.5e-3, 0.0) + 1e-3 * Vec2(std::cos(a), std::sin(a)));
  }
  const auto c = core::classify_response(window_of(pts, 1.0, true), kClearance_m);
  EXPECT_EQ(c.period, 0);
  EXPECT_EQ(c.motion, core::Motion::kQuasiPeriodic) << "K " << c.k01;
  EXPECT_LT(c.k01, 0.2);
  EXPECT_EQ(c.response, core::ResponseClass::kFullRub);  // every sample in contact, forward
}

TEST(ResponseClass, LogisticMapIsChaotic) {
  std::vector<Vec2> pts;
  double x = 0.3;
  for (int j = 0; j < 512; ++j) {
    x = 4.0 * x * (1.0 - x);
    pts.push_back(Vec2(1e-3 * (0.5 + x), 0.0));
  }
  core::ResponseWindow w = window_of(pts);
  w.contact_events = 3;
  w.samples_in_contact = 100;  // partial contact
  const auto c = core::classify_response(w, kClearance_m);
  EXPECT_EQ(c.motion, core::Motion::kChaotic) << "K " << c.k01;
  EXPECT_GT(c.k01, 0.8);
  EXPECT_EQ(c.contact, core::ContactKind::kPartial);
  EXPECT_EQ(c.response, core::ResponseClass::kChaotic);
  EXPECT_EQ(c.distinct_points, 64);  // capped
}

// The whirl's sign is the sign of the full spectrum's power-weighted
// frequency: a backward circle plus a smaller forward one is backward.
TEST(ResponseClass, WhirlDirectionFromTheFullSpectrum) {
  core::ResponseWindow w;
  const double wb = -300.0, wf = 100.0;  // rad/s
  for (int i = 0; i < 20000; ++i) {
    const double t = i * 1e-4;
    core::Sample s;
    s.t_s = t;
    // z = 1e-3 e^{i wb t} + 0.5e-3 e^{i wf t}: sum w |Z|^2 = -300 + 25 < 0.
    s.kin.rotor_pos =
        1e-3 * Vec2(std::cos(wb * t), std::sin(wb * t)) + 0.5e-3 * Vec2(std::cos(wf * t), std::sin(wf * t));
    s.kin.rotor_vel =
        1e-3 * wb * Vec2(-std::sin(wb * t), std::cos(wb * t)) + 0.5e-3 * wf * Vec2(-std::sin(wf * t), std::cos(wf * t));
    s.in_contact = true;
    w.add_sample(s);
  }
  const double expected = 1e-6 * wb + 0.25e-6 * wf;  // the mean of x y' - y x'
  EXPECT_NEAR(w.whirl_moment_sum / double(w.samples), expected, 1e-3 * std::abs(expected));
  const auto c = core::classify_response(w, kClearance_m);
  EXPECT_EQ(c.whirl, core::Whirl::kBackward);
  EXPECT_EQ(c.response, core::ResponseClass::kBackwardWhirl);
  EXPECT_EQ(c.motion, core::Motion::kTooShort);  // no Poincare points given
}

// Each enumerator, from the first to the one named last, has a name of its
// own: the bifurcation CSV's and the plots' classes, the event kinds the
// tools parse back (-Werror=switch catches a missing name, not a repeated one).
template <class Enum>
void expect_distinct_names(Enum last, const char* what) {
  std::set<std::string> names;
  for (int v = 0; v <= static_cast<int>(last); ++v) {
    const std::string name = core::to_string(static_cast<Enum>(v));
    EXPECT_TRUE(names.insert(name).second) << what << " " << name;
  }
}

TEST(ResponseClass, EveryEnumeratorHasItsOwnName) {
  expect_distinct_names(core::ContactKind::kFull, "ContactKind");
  expect_distinct_names(core::Motion::kTooShort, "Motion");
  expect_distinct_names(core::Whirl::kBackward, "Whirl");
  expect_distinct_names(core::ResponseClass::kBackwardWhirl, "ResponseClass");
  expect_distinct_names(core::EventKind::kGraze, "EventKind");
  EXPECT_STREQ(core::to_string(core::ResponseClass::kBackwardWhirl), "backward_whirl");
  EXPECT_STREQ(core::to_string(core::Motion::kQuasiPeriodic), "quasi_periodic");
  // The event kinds parse back, and a wrong name is refused naming the accepted ones.
  for (const core::EventKind k : core::kAllEventKinds) {
    EXPECT_EQ(core::value_named(core::kAllEventKinds, core::to_string(k), "event kind"), k);
  }
  try {
    core::value_named(core::kAllEventKinds, "bounce", "event kind");
    ADD_FAILURE() << "'bounce' accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "event kind 'bounce' is not accepted; accepted: touchdown, liftoff, graze");
  }
}

// Too few points for the 0-1 test: not periodic is all that is said.
TEST(ResponseClass, ShortAperiodicSeriesIsNotJudged) {
  const double golden = (std::sqrt(5.0) - 1.0) / 2.0;
  std::vector<Vec2> pts;
  for (int j = 0; j < core::kMinPointsZeroOne - 1; ++j) {
    const double a = 2 * M_PI * golden * j;
    pts.push_back(1e-3 * Vec2(std::cos(a), std::sin(a)));
  }
  core::ResponseWindow w = window_of(pts, 1.0, true);
  w.contact_events = 2;
  const auto c = core::classify_response(w, kClearance_m);
  EXPECT_EQ(c.motion, core::Motion::kAperiodic);
  EXPECT_TRUE(std::isnan(c.k01));
  EXPECT_EQ(c.response, core::ResponseClass::kAperiodicRub);
}

// On a ramp the period test uses second differences; with too few points it
// must not pass vacuously (16 points hold no second difference of period 8).
TEST(ResponseClass, DriftingPeriodNeedsEnoughComparisons) {
  std::vector<Vec2> pts;
  for (int j = 0; j < core::kMinPoints; ++j) pts.push_back(1e-3 * Vec2(std::cos(2.7 * j * j), std::sin(1.3 * j)));
  core::ResponseWindow w = window_of(pts);
  w.drifting = true;
  const auto c = core::classify_response(w, kClearance_m);
  EXPECT_EQ(c.period, 0);
  EXPECT_NE(c.motion, core::Motion::kPeriodic);
}
