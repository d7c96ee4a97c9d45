// The methods' one scan for events (event_scanner.hpp): crossing() between two
// scan points on functions whose roots are known in closed form, each way to
// a crossing and the watches under which it must not be found.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "methods/event_scanner.hpp"

using namespace rotor_rub;

namespace {

// Located within the bracket's resolution (1e-13 s near t = 1 s:
// event_time_resolution_s), with room for TOMS 748's last step.
constexpr double kLocated_s = 1e-12;
constexpr double kNone = std::numeric_limits<double>::infinity();

core::EventWatch armed() {
  core::EventWatch w;
  w.armed = true;
  return w;
}

}  // namespace

TEST(EventScanner, ScanPointsEndOnTheStepsEnd) {
  EXPECT_EQ(core::scan_points(core::Integrator::kDopri5), 2);
  EXPECT_EQ(core::scan_points(core::Integrator::kRosenbrock4), 2);
  EXPECT_EQ(core::scan_points(core::Integrator::kDop853), 4);
  EXPECT_EQ(core::scan_points(core::Integrator::kRkf78), 4);
  const double t0 = 0.1, t1 = 0.1 + 3.0e-7;
  EXPECT_EQ(core::scan_point(t0, t1, 4, 4), t1);  // exactly, whatever the rounding of the others
  EXPECT_DOUBLE_EQ(core::scan_point(t0, t1, 1, 4), t0 + 0.75e-7);
}

// A sign change counts once the function has been below zero in its regime.
TEST(EventScanner, ASignChangeOfAnArmedFunction) {
  core::RunStats stats;
  auto g = [](double t) { return t - 0.3; };
  EXPECT_NEAR(core::crossing(armed(), g, 0.0, g(0.0), 1.0, g(1.0), stats), 0.3, kLocated_s);
  EXPECT_GE(core::crossing(armed(), g, 0.0, g(0.0), 1.0, g(1.0), stats), 0.3);               // on the far side
  EXPECT_EQ(core::crossing(core::EventWatch{}, g, 0.0, g(0.0), 1.0, g(1.0), stats), kNone);  // not armed
  EXPECT_GT(stats.root_iterations, 0);
}

// A rebound starts its flight on the bore at a rate into its side: g = -r t
// + t^2 crosses back at t = r, however small r against the interval; only
// the deflated bracket g / (t - t_start) sees it, and only from the start.
TEST(EventScanner, TheDeflatedBracketFindsACrossingRightAfterAStartOnTheSurface) {
  core::RunStats stats;
  for (const double r : {1e-3, 1e-7}) {
    auto g = [r](double t) { return -r * t + t * t; };
    core::EventWatch w;
    w.regime_start_s = 0.0;
    w.start_rate = -r;
    w.on_surface = core::starts_on_surface(g(0.0), -r);
    ASSERT_TRUE(w.on_surface);
    EXPECT_NEAR(core::crossing(w, g, 0.0, g(0.0), 1.0, g(1.0), stats), r, kLocated_s) << r;
    w.regime_start_s = -1.0;  // a later interval of the regime: no start to deflate from
    EXPECT_EQ(core::crossing(w, g, 0.0, g(0.0), 1.0, g(1.0), stats), kNone) << r;
  }
  EXPECT_FALSE(core::starts_on_surface(1e-3, -1.0));   // 1 ms from its surface at that rate
  EXPECT_FALSE(core::starts_on_surface(0.0, 1.0));     // rate out of its side
  EXPECT_TRUE(core::starts_on_surface(-1e-13, -1.0));  // within kOnSurface_s
}

// A slip begun at a breakaway departs with no rate: g = t^2 (10 t - 1) dips
// below zero and crosses at t = 0.1; probed nearer the start.
TEST(EventScanner, AStartWithoutARateIsProbedNearerTheStart) {
  core::RunStats stats;
  auto g = [](double t) { return t * t * (10.0 * t - 1.0); };
  core::EventWatch w;
  w.regime_start_s = 0.0;
  w.on_surface_without_rate = true;
  EXPECT_NEAR(core::crossing(w, g, 0.0, g(0.0), 1.0, g(1.0), stats), 0.1, kLocated_s);
  w.on_surface_without_rate = false;
  EXPECT_EQ(core::crossing(w, g, 0.0, g(0.0), 1.0, g(1.0), stats), kNone);
}

// A graze between two scan points: g = 0.01 - (t - 0.5)^2 is below zero at
// both ends and crosses at 0.4 and back at 0.6. Found from the rates in
// closed form and from differences alike; not where it stays below zero, nor
// where the watch does not look for it.
TEST(EventScanner, ACrossingAndBackBetweenTwoPoints) {
  core::RunStats stats;
  for (const double peak : {0.01, -0.01}) {
    auto g = [peak](double t) { return peak - (t - 0.5) * (t - 0.5); };
    auto rate = [](double t) { return -2.0 * (t - 0.5); };
    const double want = peak > 0.0 ? 0.5 - std::sqrt(peak) : kNone;
    const double rated = core::crossing(armed(), g, rate, 0.0, g(0.0), rate(0.0), 1.0, g(1.0), rate(1.0), stats);
    const double differenced = core::crossing(armed(), g, 0.0, g(0.0), 1.0, g(1.0), stats);
    if (peak > 0.0) {
      EXPECT_NEAR(rated, want, kLocated_s);
      EXPECT_NEAR(differenced, want, kLocated_s);
    } else {
      EXPECT_EQ(rated, kNone);
      EXPECT_EQ(differenced, kNone);
    }
  }
  auto g = [](double t) { return 0.01 - (t - 0.5) * (t - 0.5); };
  core::EventWatch w = armed();
  w.interior = false;
  EXPECT_EQ(core::crossing(w, g, 0.0, g(0.0), 1.0, g(1.0), stats), kNone);
}
