// The sweep's judges of a run against its reference: the sensitivity horizon
// (where an independent witness leaves the reference's orbit) and the
// comparison of the touchdown and lift-off sequences, on hand-made traces
// whose answers are known.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "rotor_rub_sim/core/run_errors.hpp"

namespace rc = rotor_rub::core;

namespace {

// A trace sampled at 1 kHz for 10 ms whose rotor sits at x = offset(t).
template <class Offset>
rc::ReferenceTrace trace(Offset offset_m) {
  rc::ReferenceTrace t;
  for (int i = 0; i <= 10; ++i) {
    const double ts = 1e-3 * i;
    t.t_s.push_back(ts);
    t.rotor_pos_m.emplace_back(offset_m(ts), 0.0);
    t.stator_pos_m.emplace_back(0.0, 0.0);
  }
  return t;
}

rc::ContactEvent event(double t_s, rc::EventKind kind) {
  rc::ContactEvent e;
  e.t_s = t_s;
  e.kind = kind;
  return e;
}

// Feeds the reference's own samples (so the orbit error is zero) and the
// given events to an observer.
rc::RunErrors judge(const rc::ReferenceTrace& ref, const std::vector<rc::ContactEvent>& run_events,
                    double horizon_s = std::numeric_limits<double>::infinity()) {
  rc::ErrorObserver obs(ref, horizon_s);
  for (const auto& e : run_events) obs.on_event(e);
  for (std::size_t i = 0; i < ref.t_s.size(); ++i) {
    rc::Sample s;
    s.t_s = ref.t_s[i];
    s.kin.rotor_pos = ref.rotor_pos_m[i];
    s.kin.stator_pos = ref.stator_pos_m[i];
    obs.on_sample(s);
  }
  return obs.finish();
}

}  // namespace

TEST(SensitivityHorizon, TheFirstSampleWhereTheWitnessParts) {
  const auto ref = trace([](double) { return 0.0; });
  // Parting linearly at 0.1 m/s: 1e-4 m is exceeded first at t = 2 ms (2e-4 m)
  // after 1 ms sits exactly on it (1e-4 m, not above).
  const auto witness = trace([](double t) { return 0.1 * t; });
  EXPECT_DOUBLE_EQ(rc::sensitivity_horizon_s(ref, witness, 1e-4), 2e-3);
  EXPECT_EQ(rc::sensitivity_horizon_s(ref, ref, 1e-4), std::numeric_limits<double>::infinity());
  // A witness that failed at 4 ms without parting ends the horizon there.
  auto failed = trace([](double) { return 0.0; });
  failed.t_s.resize(5);
  failed.rotor_pos_m.resize(5);
  failed.failed = true;
  EXPECT_DOUBLE_EQ(rc::sensitivity_horizon_s(ref, failed, 1e-4), 4e-3);
}

TEST(RunErrors, OrbitErrorWithinTheHorizonOnly) {
  const auto ref = trace([](double) { return 0.0; });
  rc::ErrorObserver obs(ref, 5e-3);
  for (std::size_t i = 0; i < ref.t_s.size(); ++i) {
    rc::Sample s;
    s.t_s = ref.t_s[i];
    s.kin.rotor_pos = rc::Vec2(s.t_s < 4.5e-3 ? 1e-6 : 1e-3, 0.0);  // parts after the horizon's last sample
    obs.on_sample(s);
  }
  const rc::RunErrors e = obs.finish();
  EXPECT_DOUBLE_EQ(e.max_rotor_m, 1e-3);
  EXPECT_DOUBLE_EQ(e.max_rotor_in_horizon_m, 1e-6);
}

TEST(RunErrors, EventSequencesAgreeOrNameTheFirstDifference) {
  using K = rc::EventKind;
  auto ref = trace([](double) { return 0.0; });
  ref.events = {event(1e-3, K::kTouchdown), event(3e-3, K::kLiftoff), event(6e-3, K::kTouchdown),
                event(8e-3, K::kLiftoff)};
  // The same sequence, shifted by up to 2 us.
  rc::RunErrors e = judge(ref, {event(1e-3 + 1e-6, K::kTouchdown), event(3e-3 - 2e-6, K::kLiftoff),
                                event(6e-3, K::kTouchdown), event(8e-3, K::kLiftoff)});
  EXPECT_NEAR(e.max_event_err_s, 2e-6, 1e-15);
  EXPECT_TRUE(std::isnan(e.event_mismatch_s));
  // An impact that leaves at once (a graze) where the reference stays in contact.
  e = judge(ref, {event(1e-3, K::kTouchdown), event(3e-3, K::kLiftoff), event(6e-3, K::kGraze)});
  EXPECT_DOUBLE_EQ(e.event_mismatch_s, 6e-3);
  // A missed lift-off and touchdown (rolling kept on): the first difference
  // is the reference's lift-off at 3 ms, 5 ms from the run's (the window: 1 ms).
  e = judge(ref, {event(1e-3, K::kTouchdown), event(8e-3, K::kLiftoff)});
  EXPECT_DOUBLE_EQ(e.event_mismatch_s, 3e-3);
  EXPECT_EQ(e.max_event_err_s, 0.0);
  // A touchdown late by more than a window.
  e = judge(ref, {event(2.5e-3, K::kTouchdown), event(3e-3, K::kLiftoff), event(6e-3, K::kTouchdown),
                  event(8e-3, K::kLiftoff)});
  EXPECT_DOUBLE_EQ(e.event_mismatch_s, 1e-3);
  // A lift-off where the reference touches down.
  e = judge(ref, {event(1e-3, K::kTouchdown), event(3e-3, K::kTouchdown)});
  EXPECT_DOUBLE_EQ(e.event_mismatch_s, 3e-3);
  // A contact the reference does not have, after all of its own.
  e = judge(ref, {event(1e-3, K::kTouchdown), event(3e-3, K::kLiftoff), event(6e-3, K::kTouchdown),
                  event(8e-3, K::kLiftoff), event(9e-3, K::kTouchdown)});
  EXPECT_DOUBLE_EQ(e.event_mismatch_s, 9e-3);
  // Within a horizon of 5 ms only the first two count.
  e = judge(ref, {event(1e-3, K::kTouchdown), event(3e-3, K::kLiftoff), event(7e-3, K::kLiftoff)}, 5e-3);
  EXPECT_TRUE(std::isnan(e.event_mismatch_s));
}
