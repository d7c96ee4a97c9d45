// The full rub's branch traced by pseudo-arclength continuation
// (full_rub_continuation.hpp): it stays on the closed form's branches,
// passes their folds, and locates each fold where the closed form's
// discriminant (steady_response.hpp's full_rub_discriminant_N2) vanishes.
#include <gtest/gtest.h>

#include <algorithm>
#include <boost/math/tools/roots.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/full_rub_continuation.hpp"
#include "rotor_rub_sim/core/steady_response.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

// The bound on a fold's speed. The continuation's own error is far
// below: the speed is stationary at a fold, so an arclength located to
// 1e-10 of a step errs in it by the square, and the corrector's residual
// is 1e-12 of the accelerations.
constexpr double kFoldTolerance_rad_per_s = 1e-6;
// A traced point's normal force against the closed form's at its speed:
// both solve the same equations, the trace to the corrector's 1e-12 residual
// and the closed form in a quadratic's roots, whose conditioning near a fold
// (two roots merging) costs the square root of the rounding: 1e-8 there.
constexpr double kBranchTolerance = 1e-7;
// The penalty contact's fold against the rigid contact's: its bore lies
// N / k_c further out (5e-8 m at the fold's 50 N, 2.5e-4 of the clearance),
// which moves the fold by at most that fraction of its speed, 0.04 rad/s
// (measured: 4.2e-4 rad/s, at k_c 1e9 N/m); and by more than the
// continuation's own error, so the trace is the penalty contact's.
constexpr double kPenaltyFoldShift_rad_per_s = 0.04;
constexpr double kOwnFoldShift_rad_per_s = 1e-6;
// Within this distance of a fold the branch's least stable eigenvalue is
// near 0 (as the square root of the distance) and a Newton from the closed
// form nearly singular: the stability verdicts and the penalty's Newton
// comparisons are taken outside it.
constexpr double kNearFold_rad_per_s = 1.0;
// Just inside a discriminant's zero, where both roots are still real.
constexpr double kInside_rad_per_s = 1e-6;

// The folds of p's full rub in [lo, hi]: the zeros of the discriminant where
// the two roots are positive (the branch's two full rubs meet), to the
// double's resolution (TOMS 748 on a grid's sign changes).
std::vector<double> discriminant_folds(const core::ModelParameters& p, double lo, double hi) {
  std::vector<double> folds;
  auto disc = [&p](double w) { return core::full_rub_discriminant_N2(p, w); };
  constexpr int kGrid = 4000;
  double w0 = lo, d0 = disc(lo);
  for (int i = 1; i <= kGrid; ++i) {
    const double w1 = lo + (hi - lo) * i / kGrid, d1 = disc(w1);
    if ((d0 < 0.0) != (d1 < 0.0)) {
      std::uintmax_t it = 200;
      const auto bracket =
          boost::math::tools::toms748_solve(disc, w0, w1, d0, d1, boost::math::tools::eps_tolerance<double>(52), it);
      const double w = 0.5 * (bracket.first + bracket.second);
      // A fold of positive normal forces: just inside, both roots are positive.
      const double inside = d0 > 0.0 ? w - kInside_rad_per_s : w + kInside_rad_per_s;
      if (core::synchronous_full_rub(p, inside).size() == 2) folds.push_back(w);
    }
    w0 = w1;
    d0 = d1;
  }
  return folds;
}

// The branch from the upper full rub at `start` toward higher speeds.
core::FullRubBranch trace(const core::ModelParameters& p, double start, double lo, double hi) {
  const auto rubs = core::full_rub_stability(p, start);
  if (rubs.empty()) {
    ADD_FAILURE() << "no full rub at " << start;
    return {};
  }
  core::ContinuationSettings settings;
  settings.min_speed_rad_per_s = lo;
  settings.max_speed_rad_per_s = hi;
  return core::continue_full_rub(core::turning_rotor(p), core::station_stator(p), p.clearance_m, p.friction_coefficient,
                                 rubs.front(), start, settings);
}

struct FoldCase {
  const char* name;
  core::StatorModel stator;
  double friction;
};

// The paper's rotor on a rigid stator at f = 0.3 and 0.5 and on its elastic
// stator at f = 0.3: the fold of each branch, traced from its upper full rub
// below it, where the discriminant vanishes; past it the trace turns back
// onto the lower branch (the closed form's smaller root), unstable, and the
// stability changes at the fold (an eigenvalue through 0: a saddle-node).
TEST(FullRubContinuation, FoldsAreWhereTheDiscriminantVanishes) {
  for (const FoldCase& c : {FoldCase{"rigid stator, f = 0.3", core::StatorModel::kRigid, 0.3},
                            FoldCase{"rigid stator, f = 0.5", core::StatorModel::kRigid, 0.5},
                            FoldCase{"elastic stator, f = 0.3", core::StatorModel::kElastic, 0.3}}) {
    SCOPED_TRACE(c.name);
    const core::ModelParameters p = test::paper_model(c.stator, c.friction);
    const std::vector<double> folds = discriminant_folds(p, 20.0, 2000.0);
    ASSERT_FALSE(folds.empty());
    const double fold = folds.front();
    const double start = fold - 10.0;
    const core::FullRubBranch branch = trace(p, start, start - 50.0, fold + 50.0);
    ASSERT_FALSE(branch.folds_rad_per_s.empty()) << branch.end;
    EXPECT_NEAR(branch.folds_rad_per_s.front(), fold, kFoldTolerance_rad_per_s);
    std::printf("%s: fold at %.9f rad/s, the discriminant's %+.2e off; %zu points, ended by %s\n", c.name,
                branch.folds_rad_per_s.front(), branch.folds_rad_per_s.front() - fold, branch.points.size(),
                branch.end.c_str());
    ASSERT_FALSE(branch.stability_changes_rad_per_s.empty());
    EXPECT_NEAR(branch.stability_changes_rad_per_s.front(), fold, kFoldTolerance_rad_per_s);
    // Every point on one of the closed form's two full rubs at its speed:
    // the upper (stable) up to the fold, then the lower (unstable), never
    // back.
    bool past_fold = false;
    for (const core::FullRubBranchPoint& pt : branch.points) {
      const auto closed = core::synchronous_full_rub(p, pt.speed_rad_per_s);
      ASSERT_EQ(closed.size(), 2u) << pt.speed_rad_per_s;
      const double upper = closed[0].normal_force_N, lower = closed[1].normal_force_N;
      const bool on_lower = std::abs(pt.rub.normal_force_N - lower) < std::abs(pt.rub.normal_force_N - upper);
      EXPECT_TRUE(on_lower || !past_fold) << pt.speed_rad_per_s << ": back on the upper branch";
      past_fold = past_fold || on_lower;
      const double n = on_lower ? lower : upper;
      EXPECT_NEAR(pt.rub.normal_force_N, n, kBranchTolerance * n) << pt.speed_rad_per_s;
      if (std::abs(pt.speed_rad_per_s - fold) > kNearFold_rad_per_s) {
        EXPECT_EQ(pt.rub.stable(), !on_lower) << pt.speed_rad_per_s;
      }
    }
    EXPECT_TRUE(past_fold);
    EXPECT_EQ(branch.end.rfind("the normal force's fall to 0 near", 0), 0u) << branch.end;
  }
}

// The penalty contact's branch (the penalty method's scenes, k_c 1e9 N/m):
// every traced point away from the fold is the rest point
// full_rub_stability finds by Newton from the rigid closed form with the
// bore moved out by N / k_c, and the fold lies near the rigid contact's.
TEST(FullRubContinuation, ThePenaltyContactsBranch) {
  const core::ModelParameters p = test::paper_model(core::StatorModel::kElastic, 0.1);
  const auto rubs = core::full_rub_stability(p, 150.0, true);
  ASSERT_FALSE(rubs.empty());
  const core::PenaltyContact penalty{p.contact_stiffness_N_per_m,
                                     core::contact_damping_N_s_per_m(core::StationModel(p))};
  core::ContinuationSettings settings;
  settings.min_speed_rad_per_s = 140.0;
  settings.max_speed_rad_per_s = 200.0;
  const core::FullRubBranch branch =
      core::continue_full_rub(core::turning_rotor(p), core::station_stator(p), p.clearance_m, p.friction_coefficient,
                              rubs.front(), 150.0, settings, &penalty);
  ASSERT_EQ(branch.folds_rad_per_s.size(), 1u) << branch.end;
  const double rigid = discriminant_folds(p, 140.0, 200.0).front();
  std::printf("penalty contact: fold at %.9f rad/s, the rigid contact's %+.3e off\n", branch.folds_rad_per_s.front(),
              branch.folds_rad_per_s.front() - rigid);
  EXPECT_NEAR(branch.folds_rad_per_s.front(), rigid, kPenaltyFoldShift_rad_per_s);
  EXPECT_GT(std::abs(branch.folds_rad_per_s.front() - rigid), kOwnFoldShift_rad_per_s);
  int compared = 0;
  for (const core::FullRubBranchPoint& pt : branch.points) {
    if (std::abs(pt.speed_rad_per_s - rigid) < kNearFold_rad_per_s) continue;
    const auto newton = core::full_rub_stability(p, pt.speed_rad_per_s, true);
    double nearest = 1e300;
    for (const auto& r : newton) nearest = std::min(nearest, std::abs(r.normal_force_N - pt.rub.normal_force_N));
    EXPECT_LT(nearest, kBranchTolerance * pt.rub.normal_force_N) << pt.speed_rad_per_s;
    ++compared;
  }
  EXPECT_GT(compared, 10);
}

// The trace ends where it should: at the speed range's end, or where the
// lower branch's normal force falls to 0 (it meets the free orbit).
TEST(FullRubContinuation, TheTraceSaysWhyItEnded) {
  const core::ModelParameters p = test::paper_model(core::StatorModel::kElastic, 0.1);
  const core::FullRubBranch up = trace(p, 150.0, 140.0, 160.0);
  EXPECT_TRUE(up.folds_rad_per_s.empty());
  EXPECT_EQ(up.end, "the speed range's end");
  EXPECT_GT(up.points.back().speed_rad_per_s, 159.0);
  const core::FullRubBranch through = trace(p, 150.0, 100.0, 200.0);
  ASSERT_EQ(through.folds_rad_per_s.size(), 1u);
  EXPECT_NEAR(through.folds_rad_per_s.front(), discriminant_folds(p, 100.0, 200.0).front(), kFoldTolerance_rad_per_s);
  EXPECT_FALSE(through.end.empty());
  core::ContinuationSettings bad;
  bad.min_speed_rad_per_s = 200.0;
  bad.max_speed_rad_per_s = 300.0;
  EXPECT_THROW(core::continue_full_rub(core::turning_rotor(p), core::station_stator(p), p.clearance_m, 0.1,
                                       core::full_rub_stability(p, 150.0).front(), 150.0, bad),
               std::invalid_argument);
}

}  // namespace
