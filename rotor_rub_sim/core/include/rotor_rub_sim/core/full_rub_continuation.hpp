/// @file
/// The synchronous full rub's branch traced in the speed by pseudo-arclength
/// continuation (Keller): the rest point in the turning frame, G(q, w) = 0
/// (full_rub_stability.hpp's accelerations at zero rates), followed along
/// its arclength in scaled coordinates (each coordinate by its size at the
/// start, at least the clearance, an angle by 1 rad, the speed by the start's),
/// so that the trace passes the folds where the branch turns back in speed
/// (the two full rubs of a speed meet and vanish there), which a sweep in the
/// speed cannot pass: a tangent predictor, a Newton corrector on the
/// hyperplane normal to the tangent, the Jacobian by central differences.
/// Every point is linearised (its eigenvalues); the folds are located where
/// dw/ds = 0 and the changes of stability where the least stable
/// eigenvalue's real part crosses 0, each by regula falsi (Illinois) along
/// the arclength. Tests: test_full_rub_continuation.cpp (the folds against
/// the closed form's discriminant, full_rub_discriminant).
#pragma once

#include <string>
#include <vector>

#include "rotor_rub_sim/core/full_rub_stability.hpp"

namespace rotor_rub::core {

/// How a branch is traced.
struct ContinuationSettings {
  double min_speed_rad_per_s = 0.0;  ///< the trace stops where the speed leaves [min, max]
  double max_speed_rad_per_s = 0.0;  ///< see min_speed_rad_per_s
  double step = 0.01;                ///< the first arclength step (scaled units, above)
  double max_step = 0.05;            ///< the longest step (grown after easy corrections)
  int max_points = 5000;             ///< the trace stops after this many points
  bool increasing_speed = true;      ///< the direction the trace leaves the start in
};

/// A point of a branch, linearised.
struct FullRubBranchPoint {
  double speed_rad_per_s = 0.0;
  FullRubStability rub;
};

/// A traced branch.
struct FullRubBranch {
  std::vector<FullRubBranchPoint> points;           ///< in the order traced
  std::vector<double> folds_rad_per_s;              ///< where the branch turns back in speed
  std::vector<double> stability_changes_rad_per_s;  ///< where the least stable eigenvalue's real part crosses 0
  std::string end;  ///< what stopped the trace: "the speed range's end", "the normal force's fall to 0 ...", ...
};

/// The branch through `start` (a full rub at start_speed_rad_per_s, from
/// full_rub_stability: its state's positions are the rest point), traced
/// both ways is two calls. The rigid contact, or the penalty contact's
/// (penalty). The trace ends where the speed leaves the settings' range,
/// where the normal force falls to 0 (the branch meets the free orbit: the
/// contact ends), after max_points, where the corrector fails or the tangent
/// turns too fast at the smallest step, or where a point cannot be
/// linearised (said in `end`; the points traced so far stand). Throws
/// std::invalid_argument for an empty range, or a start at a speed not above
/// 0 or outside the range.
FullRubBranch continue_full_rub(const TurningRotor& rotor, const StationStator& stator, double clearance_m,
                                double friction_coefficient, const FullRubStability& start,
                                double start_speed_rad_per_s, const ContinuationSettings& settings,
                                const PenaltyContact* penalty = nullptr);

}  // namespace rotor_rub::core
