// What the rotor does at a speed, once the transient has died: the classes of
// a bifurcation diagram, judged from the keyphasor's Poincare points and the
// samples of the same time window (ResponseWindow collects both).
//
// How each attribute is decided (names: to_string below):
// * contact: the share of samples in contact (and whether any contact event
//   happened in the window): none (0, no event), full (every sample in
//   contact, no lift-off: annular rub), partial (the rest).
// * motion, from the Poincare points p_1..p_M of the rotor relative to the
//   stator (one per revolution): period n when p_{j+n} = p_j within
//   kPeriodTolerance (of the clearance) for every j, n <= kMaxPeriod, seen
//   in kMinComparisons comparisons at least;
//   otherwise the 0-1 test for chaos (Gottwald & Melbourne 2009, correlation
//   form, median over 32 frequencies c in (pi/5, 4 pi/5) from a fixed seed)
//   on the series |p_j|: K >= kChaosK chaotic, else quasi-periodic (with at
//   least kMinPointsZeroOne points; fewer: aperiodic, not judged).
//   On a slow ramp (a drifting window) the period-n points move with the
//   speed: the test is then on the second differences
//   p_{j+2n} - 2 p_{j+n} + p_j (zero for a smooth drift, of the orbit's size
//   otherwise), and the 0-1 test runs on |p_j| less its linear trend.
// * whirl: the sign of the time mean of x y' - y x' over the samples of the
//   rotor's orbit. For z = x + i y = sum_k Z_k e^{i w_k t} that mean is
//   sum_k w_k |Z_k|^2 (Parseval): the sign of the full spectrum's
//   power-weighted frequency, + forward (with the spin), - backward.
// * class, for charts: no_contact; backward_whirl (in contact and whirling
//   backward: dry whirl/whip); full_rub (annular, forward); partial_rub
//   (periodic); quasi_periodic, chaotic (in contact); aperiodic_rub (in
//   contact, not shown periodic: too few points to judge).
#pragma once

#include <string>
#include <vector>

#include "rotor_rub_sim/core/simulation.hpp"

namespace rotor_rub::core {

enum class ContactKind { kNone, kPartial, kFull };
enum class Motion { kPeriodic, kQuasiPeriodic, kChaotic, kAperiodic, kTooShort };
enum class Whirl { kForward, kBackward };
enum class ResponseClass { kNoContact, kFullRub, kPartialRub, kQuasiPeriodic, kChaotic, kAperiodicRub, kBackwardWhirl };

// The names in the bifurcation tool's CSV and the docs (snake case).
const char* to_string(ContactKind v);
const char* to_string(Motion v);
const char* to_string(Whirl v);
const char* to_string(ResponseClass v);

// Points closer than this share of the clearance are the same point.
inline constexpr double kPeriodTolerance = 1e-4;
inline constexpr int kMaxPeriod = 8;
inline constexpr int kMinComparisons = 8;
// At least this many Poincare points to judge the motion (period 8 needs
// 16 to be seen twice; the 0-1 test needs many more to be meaningful).
inline constexpr int kMinPoints = 16;
inline constexpr double kChaosK = 0.5;
// The 0-1 test needs a long series: on 128 Poincare points of the paper
// rotor's quasi-periodic partial rub it gave K 0.5-0.95 ("chaotic"), on 512
// points of the same runs K < 0.21. Below this many points a motion that is
// not periodic is "aperiodic" (not judged).
inline constexpr int kMinPointsZeroOne = 400;

struct PoincarePoint {
  double t_s = 0.0;
  double speed_rad_per_s = 0.0;
  Vec2 relative_m = Vec2::Zero();  // rotor minus stator centre
  bool in_contact = false;
  double normal_force_N = 0.0;
};

// The samples and Poincare points of one time window.
struct ResponseWindow {
  std::vector<PoincarePoint> points;
  long samples = 0, samples_in_contact = 0, contact_events = 0;
  double whirl_moment_sum = 0.0;                        // sum of x y' - y x' of the rotor [m^2/s]
  double max_relative_m = 0.0, min_relative_m = 1e300;  // |r_r - r_s| over the samples
  double normal_force_sum_N = 0.0;
  bool drifting = false;  // recorded on a speed ramp (see the period test)

  void add_sample(const Sample& s);
  void add_point(const Sample& s);
};

struct ResponseClassification {
  ContactKind contact = ContactKind::kNone;
  Motion motion = Motion::kTooShort;
  int period = 0;           // for kPeriodic
  double k01 = 0.0;         // the 0-1 test's K (NaN when not run)
  int distinct_points = 0;  // Poincare points more than the tolerance apart (up to 64)
  Whirl whirl = Whirl::kForward;
  double contact_fraction = 0.0;     // samples in contact / samples
  double mean_normal_force_N = 0.0;  // over all samples of the window
  ResponseClass response = ResponseClass::kNoContact;
};

ResponseClassification classify_response(const ResponseWindow& w, double clearance_m);

// The 0-1 test's K for a series (correlation method, modified by removing
// the oscillating term), median over 32 frequencies from a fixed seed.
double zero_one_test_k(const std::vector<double>& phi);

}  // namespace rotor_rub::core
