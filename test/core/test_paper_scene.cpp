// The paper's run-up against our own tight reference: switching at rtol 1e-10.
#include <gtest/gtest.h>

#include <cmath>

#include "rotor_rub_sim/core/trajectory_compare.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

constexpr double kRate_hz = 10000.0;  // error sampled every 0.1 ms

const test::Run& reference() {
  static const test::Run ref = [] {
    core::Scene s = test::with_method(test::paper_scene(), core::Method::kSwitching, 1e-10, 1e-13);
    s.output_rate_hz = kRate_hz;
    return test::run(s);
  }();
  return ref;
}

test::Run run_at(core::Method m, double rtol, double atol) {
  core::Scene s = test::with_method(test::paper_scene(), m, rtol, atol);
  s.output_rate_hz = kRate_hz;
  return test::run(s);
}

// Max |x_r - x_r,ref| over samples with t <= t_end_s.
double max_error_until(const test::Run& r, double t_end_s) {
  std::vector<core::Sample> a, b;
  for (std::size_t i = 0; i < r.out.samples.size() && r.out.samples[i].t_s <= t_end_s; ++i) {
    a.push_back(r.out.samples[i]);
    b.push_back(reference().out.samples[i]);
  }
  return core::compare_trajectories(a, b).max_rotor_x_m;
}

// The bars of issue 2 (README "Accuracy and speed").
constexpr double kFirstContactBar_s = 1e-4;
constexpr double kSwitchingBar_m = 1e-7;
constexpr double kIterationBar_m = 1e-5;
// Penalty, e = 0: the clamped critical damper leaves an impact with exp(-2)
// of its closing speed where the plastic law leaves with 0 (contact_law.hpp).
// Through the sustained contact this costs < 2e-6 m; the 3.6 cm/s impacts at
// 2.88 s and 2.93 s then leave the runs 2.4e-5 m apart in free flight,
// whatever k_c (1e9: 3.5e-5, 1e10: 3.7e-5 m). So the penalty is held to the
// bar through the sustained contact, and to 5e-5 m (measured 3.6e-5) over
// the whole run: a contact-law difference, not a numerical error.
constexpr double kPenaltyBar_m = 2e-5;
constexpr double kPenaltySustainedEnd_s = 2.85;
constexpr double kPenaltyWholeRun_m = 5e-5;

}  // namespace

TEST(PaperScene, ReferenceTouchesDownAndLiftsOffWhereExpected) {
  const auto& ref = reference();
  ASSERT_FALSE(ref.result.failure);
  const double first = core::first_contact_s(ref.out.events);
  const auto sustained = core::longest_contact(ref.out.events);
  // The paper reads 1.14 s and 2.6 s off its Figure 7 (ode45, rtol 1e-3);
  // ours: first contact 1.1129 s, sustained contact 1.1136 .. 2.7949 s.
  EXPECT_NEAR(first, 1.1129, 1e-3);
  EXPECT_NEAR(sustained.first, 1.1136, 1e-3);
  EXPECT_NEAR(sustained.second, 2.7949, 1e-3);
}

TEST(PaperScene, SwitchingMeetsItsBar) {
  const test::Run r = run_at(core::Method::kSwitching, 1e-7, 1e-10);
  ASSERT_FALSE(r.result.failure);
  EXPECT_LE(max_error_until(r, 4.0), kSwitchingBar_m);
  EXPECT_NEAR(core::first_contact_s(r.out.events), core::first_contact_s(reference().out.events), kFirstContactBar_s);
}

TEST(PaperScene, IterationMeetsItsBar) {
  const test::Run r = run_at(core::Method::kIteration, 1e-5, 1e-8);
  ASSERT_FALSE(r.result.failure);
  EXPECT_LE(max_error_until(r, 4.0), kIterationBar_m);
  EXPECT_NEAR(core::first_contact_s(r.out.events), core::first_contact_s(reference().out.events), kFirstContactBar_s);
}

TEST(PaperScene, PenaltyAgreesWithinTheContactLawDifference) {
  const test::Run r = run_at(core::Method::kPenalty, 1e-6, 1e-9);
  ASSERT_FALSE(r.result.failure);
  EXPECT_LE(max_error_until(r, kPenaltySustainedEnd_s), kPenaltyBar_m);
  EXPECT_LE(max_error_until(r, 4.0), kPenaltyWholeRun_m);
  EXPECT_NEAR(core::first_contact_s(r.out.events), core::first_contact_s(reference().out.events), kFirstContactBar_s);
}

TEST(PaperScene, ErrorFallsAsToleranceTightens) {
  for (auto m : {core::Method::kSwitching, core::Method::kIteration}) {
    const double loose = max_error_until(run_at(m, 1e-4, 1e-7), 4.0);
    const double tight = max_error_until(run_at(m, 1e-7, 1e-10), 4.0);
    EXPECT_LT(tight, 0.1 * loose) << core::to_string(m) << " loose " << loose << " tight " << tight;
  }
}

TEST(PaperScene, PenaltyErrorFallsAsContactStiffnessGrows) {
  // Through the sustained contact, where the contact law's rebound plays no
  // part, the penalty's compliance is the error: it falls with k_c.
  std::vector<double> err;
  for (double kc : {1e6, 1e7, 1e8}) {
    core::Scene s = test::with_method(test::paper_scene(), core::Method::kPenalty, 1e-8, 1e-11);
    s.model.contact_stiffness_N_per_m = kc;
    s.output_rate_hz = kRate_hz;
    err.push_back(max_error_until(test::run(s), 2.7));
  }
  EXPECT_LT(err[1], err[0]);
  EXPECT_LT(err[2], err[1]);
}
