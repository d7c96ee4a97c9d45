#include "rotor_rub_sim/core/orbit_continuation.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "orbit_equations.hpp"
#include "orbit_shot.hpp"
#include "regula_falsi.hpp"

namespace rotor_rub::core {

const char* to_string(OrbitBifurcationKind kind) {
  switch (kind) {
    case OrbitBifurcationKind::kFold:
      return "fold";
    case OrbitBifurcationKind::kPeriodDoubling:
      return "period_doubling";
    case OrbitBifurcationKind::kNeimarkSacker:
      return "neimark_sacker";
  }
  return "?";
}

namespace {

// The smallest step, where a trace that keeps failing ends.
constexpr double kMinStep = 1e-7;
// A step whose tangent turns by more than this angle's cosine (18 deg) is
// taken again at half the length (full_rub_continuation.cpp's reason).
constexpr double kMinTurnCosine = 0.95;
// A bifurcation's regula falsi stops on a bracket of this fraction of the step.
constexpr double kLocateFraction = 1e-8;
// A multiplier this far from the real axis, relative to its modulus, is complex.
constexpr double kRealAxis = 1e-9;
// A doubled orbit whose two halves differ by less than this (in C and C w)
// is the single period's.
constexpr double kSameHalves = 1e-6;
// A doubled branch's fold where the orbit of half its period has a
// multiplier this near -1 is where the two branches meet.
constexpr double kMeetsHalf = 1e-3;
// The doubled branch's first step, a fraction of the settings' step.
constexpr double kFirstDoubledStep = 0.05;
// An event nearer the section than this fraction of the orbit's period
// moves the section to the middle of the longest stretch without events:
// an event that crosses the section would change the section's regime and
// the events' order, which the trace reads as the end of the branch.
constexpr double kSectionMargin = 1.0 / 16.0;

using Vector = Eigen::VectorXd;

// The test functions of the bifurcations: det(M + I) (a real multiplier at
// -1), and the complex multipliers outside the unit circle.
double doubling_test(const PeriodicOrbit& o) {
  return (o.monodromy + Eigen::MatrixXd::Identity(o.monodromy.rows(), o.monodromy.cols())).determinant();
}
// The complex multipliers, and those of them outside the unit circle.
int complex_count(const PeriodicOrbit& o, bool outside_only) {
  int count = 0;
  for (const auto& mu : o.multipliers) {
    count += std::abs(mu.imag()) > kRealAxis * std::abs(mu) && (!outside_only || std::abs(mu) > 1.0);
  }
  return count;
}
// The complex pair's modulus nearest the unit circle, less 1 (0 without one).
double complex_modulus_test(const PeriodicOrbit& o) {
  double best = INFINITY, value = 0.0;
  for (const auto& mu : o.multipliers) {
    if (std::abs(mu.imag()) <= kRealAxis * std::abs(mu)) continue;
    if (std::abs(std::abs(mu) - 1.0) < best) {
      best = std::abs(std::abs(mu) - 1.0);
      value = std::abs(mu) - 1.0;
    }
  }
  return value;
}

// Where an event lies within kSectionMargin of the orbit's section, the
// section moves to the middle of its longest stretch in free flight (of an
// orbit that never leaves the bore, between any two events): the
// equations, their chart, the unknowns and the tangent there, its
// orientation from the previous point carried to the new section as well
// (else the flow's Jacobian on t, which leaves out the speed's share).
// Returns false where it stays.
bool resection(OrbitEquations& g, const PeriodicOrbit& o, const PeriodicOrbit* previous, Vector& Y, Vector& t) {
  if (o.events.empty()) return false;
  const double w = o.speed_rad_per_s, t0 = o.section_angle_rad / w, span = o.period_s;
  std::vector<double> tau;  // the events' times after the section, in (0, span], in order
  for (const OrbitEvent& e : o.events) tau.push_back(e.time_s - t0);
  if (std::min(tau.front(), span - tau.back()) >= kSectionMargin * span) return false;
  const bool flies =
      std::any_of(o.events.begin(), o.events.end(), [](const OrbitEvent& e) { return starts_flight(e.kind); });
  const std::size_t m = tau.size();
  double best = -1.0, middle = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    if (flies && !starts_flight(o.events[i].kind)) continue;
    const double next = i + 1 < m ? tau[i + 1] : tau.front() + span;
    if (next - tau[i] > best) {
      best = next - tau[i];
      middle = std::fmod(0.5 * (tau[i] + next), span);
    }
  }
  if (best < 2.0 * kSectionMargin * span) return false;  // no better place
  OrbitSettings s = g.settings();
  const RubFlow flow = g.flow_at(o.parameter);
  const int n = static_cast<int>(o.state.size()), last = static_cast<int>(Y.size()) - 1;
  const OrbitShot to_new = shoot(flow, flow.scaled(o.state), t0, t0 + middle, s, true);
  Vector direction(n + 1);  // in the state space
  direction.head(n) = to_new.jacobian * g.state_direction(t.head(last));
  direction(n) = t(last);
  if (previous != nullptr && previous->section_angle_rad == o.section_angle_rad) {
    // The same spin angle on: the previous orbit's own time to it.
    const double wp = previous->speed_rad_per_s, tp = previous->section_angle_rad / wp;
    const RubFlow flow_p = g.flow_at(previous->parameter);
    const Vector moved = shoot(flow_p, flow_p.scaled(previous->state), tp, tp + middle * w / wp, s, false).end;
    direction.head(n) = to_new.end - moved;
    direction(n) = Y(last) - previous->parameter / g.start_value();
  }
  s.section_angle_rad = std::fmod(s.section_angle_rad + w * middle, 2.0 * M_PI);
  const OrbitShot round = shoot(flow, to_new.end, t0 + middle, t0 + middle + span, s, false);
  g = g.with(s, round.events).charted(flow, to_new.end, to_new.ends_in_stick ? 2 : to_new.ends_in_contact ? 1 : 0);
  const Vector z = g.in_contact() ? Vector::Zero(g.coordinates(to_new.end).size()) : to_new.end;
  Y.resize(z.size() + 1);
  Y.head(z.size()) = z;
  Y(z.size()) = o.parameter / g.start_value();
  Vector chart_direction(z.size() + 1);
  chart_direction.head(z.size()) = g.coordinates(direction.head(n));
  chart_direction(z.size()) = direction(n);
  t = g.tangent(Y, chart_direction);
  return true;
}

// In contact the chart moves with the branch to each new point (its
// tangent space there), the tangent carried over through the state space.
void rechart(OrbitEquations& g, const PeriodicOrbit& o, Vector& Y, Vector& t) {
  if (!g.in_contact()) return;
  const int last = static_cast<int>(Y.size()) - 1;
  const Vector direction = g.state_direction(t.head(last));
  g = g.at(o);
  Vector chart_direction(last + 1);
  chart_direction.head(last) = g.coordinates(direction);
  chart_direction(last) = t(last);
  Y = g.unknowns(o);
  t = g.tangent(Y, chart_direction);
}

// Whether orbit o of an even number of periods is the orbit of half its
// period traced twice (its two halves agree).
bool halves_agree(const ModelParameters& p, const OrbitSettings& s, const PeriodicOrbit& o) {
  if (o.periods % 2 != 0) return false;
  const RubFlow flow(p, o.speed_rad_per_s, settle_apex_m(p, s));
  const double t0 = o.section_angle_rad / o.speed_rad_per_s;
  const OrbitShot half = shoot(flow, flow.scaled(o.state), t0, t0 + 0.5 * o.period_s, s, false);
  return (half.end - half.start).lpNorm<Eigen::Infinity>() < kSameHalves;
}

// Whether a fold of the doubled branch at orbit o is where it meets the
// orbit of half its period: that orbit, found by Newton from o's state at
// o's speed, has a multiplier at -1 (to kMeetsHalf: the fold's location
// along a branch whose speed is stationary there).
bool meets_half(const ModelParameters& p, const OrbitSettings& s, const PeriodicOrbit& o) {
  if (o.periods % 2 != 0) return false;
  OrbitSettings half = s;
  half.periods = o.periods / 2;
  half.section_angle_rad = o.section_angle_rad;
  try {
    const PeriodicOrbit single = find_periodic_orbit(p, o.speed_rad_per_s, o.state, half);
    double nearest = INFINITY;
    for (const auto& mu : single.multipliers) nearest = std::min(nearest, std::abs(mu + 1.0));
    return nearest < kMeetsHalf;
  } catch (const OrbitError&) {
    return false;
  }
}

// The trace from Y along t (the first point already in the branch).
void trace(OrbitEquations g, Vector Y, Vector t, const ContinuationSettings& settings, double ds, OrbitBranch& branch) {
  resection(g, branch.points.back(), nullptr, Y, t);
  std::string last_error;  // why the step was last halved
  while (true) {
    const int n = static_cast<int>(Y.size()) - 1;  // the parameter's index (a section's move can change it)
    if (static_cast<int>(branch.points.size()) >= settings.max_points) {
      branch.end = "max_points (" + std::to_string(settings.max_points) + ")";
      return;
    }
    if (ds < kMinStep) {
      // A step that meets what the branch cannot pass (a grazing, a section
      // inside the bore, a slip at rest tangentially) was halved down to the smallest:
      // the trace ends as close to it as that step.
      branch.end = last_error + " (after the last point, at " + g.describe(branch.points.back().parameter) + ")";
      return;
    }
    try {
      Vector Y_new;
      int iterations = 0;
      if (!g.correct(Y + ds * t, t, Y_new, iterations)) {
        last_error = "the corrector's failure at the smallest step";
        ds *= 0.5;
        continue;
      }
      const Vector t_new = g.tangent(Y_new, t);
      if (t.dot(t_new) < kMinTurnCosine) {
        last_error = "a turn of the tangent at the smallest step";
        ds *= 0.5;
        continue;
      }
      auto point_at = [&](double s) {
        Vector Ys;
        int its = 0;
        if (!g.correct(Y + s * t, t, Ys, its)) {
          throw OrbitError("the corrector failed inside a step at " + std::to_string(g.speed(Y)) + " rad/s");
        }
        return Ys;
      };
      const PeriodicOrbit orbit = g.orbit(Y_new, iterations);
      const PeriodicOrbit& last = branch.points.back();
      // Located inside this step, kept only once the step is accepted.
      std::vector<OrbitBifurcation> found;
      auto locate = [&](OrbitBifurcationKind kind, const std::function<double(double)>& test, double f0, double f1) {
        const double s = regula_falsi(test, f0, ds, f1, kLocateFraction);
        const PeriodicOrbit o = g.orbit(point_at(s));
        found.push_back({kind, o.speed_rad_per_s, o.parameter, o});
      };
      if (t(n) * t_new(n) < 0.0) {
        locate(
            OrbitBifurcationKind::kFold, [&](double s) { return g.tangent(point_at(s), t)(n); }, t(n), t_new(n));
        if (meets_half(g.model_at(found.back().parameter), g.settings(), found.back().orbit)) {
          // The doubled branch turns back where it meets the orbit of half
          // its period (a pitchfork of its map): that is the single orbit's
          // period doubling, not a fold, and past it the trace would follow
          // the single orbit traced twice.
          branch.end = "the orbit meets the orbit of half its period at " + g.describe(found.back().parameter) +
                       " (its period doubling)";
          return;
        }
      }
      const double d0 = doubling_test(last), d1 = doubling_test(orbit);
      if ((d0 < 0.0) != (d1 < 0.0)) {
        locate(
            OrbitBifurcationKind::kPeriodDoubling, [&](double s) { return doubling_test(g.orbit(point_at(s))); }, d0,
            d1);
      }
      // A pair crossing the circle: as many complex multipliers on both
      // sides (none merged into or split from a real pair), a different
      // count outside, and the pair's modulus through 1.
      const double m0 = complex_modulus_test(last), m1 = complex_modulus_test(orbit);
      if (complex_count(last, false) == complex_count(orbit, false) &&
          complex_count(last, true) != complex_count(orbit, true) && (m0 < 0.0) != (m1 < 0.0)) {
        locate(
            OrbitBifurcationKind::kNeimarkSacker, [&](double s) { return complex_modulus_test(g.orbit(point_at(s))); },
            m0, m1);
      }
      const double v_new = orbit.parameter;
      if (v_new < settings.min_speed_rad_per_s || v_new > settings.max_speed_rad_per_s) {
        // The last point at the range's end itself, by Newton at that value.
        const double edge =
            v_new < settings.min_speed_rad_per_s ? settings.min_speed_rad_per_s : settings.max_speed_rad_per_s;
        try {
          OrbitSettings at_last = g.settings();
          at_last.section_angle_rad = last.section_angle_rad;  // (g's may have moved since)
          PeriodicOrbit at_edge = find_periodic_orbit(g.model_at(edge), g.speed_at(edge), last.state, at_last);
          at_edge.parameter = edge;
          if (event_kinds(at_edge.events) == event_kinds(last.events)) branch.points.push_back(at_edge);
        } catch (const OrbitError&) {
          // (the last point stands)
        }
        branch.end = "the range's end";
        return;
      }
      for (auto& bifurcation : found) {
        bifurcation.after_point = branch.points.size() - 1;
        branch.bifurcations.push_back(bifurcation);
      }
      branch.points.push_back(orbit);
      Y = Y_new;
      t = t_new;
      if (!resection(g, orbit, &branch.points[branch.points.size() - 2], Y, t)) rechart(g, orbit, Y, t);
      if (iterations <= 2) ds = std::min(1.5 * ds, settings.max_step);
    } catch (const OrbitError& e) {
      last_error = e.what();
      ds *= 0.5;
    }
  }
}

// An orbit whose section lies in a contact phase (a lift-off follows) taken
// again at a section in free flight: the middle of its longest free
// stretch. OrbitError for an orbit with no free flight.
PeriodicOrbit free_section(const ModelParameters& p, const PeriodicOrbit& o, const OrbitSettings& s) {
  const double w = o.speed_rad_per_s, t0 = o.section_angle_rad / w;
  const std::size_t m = o.events.size();
  double best = -1.0, middle = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    if (!starts_flight(o.events[i].kind)) continue;  // a contact follows it
    const double next = i + 1 < m ? o.events[i + 1].time_s : o.events.front().time_s + o.period_s;
    if (next - o.events[i].time_s > best) {
      best = next - o.events[i].time_s;
      middle = 0.5 * (o.events[i].time_s + next) - t0;
    }
  }
  if (best < 0.0) throw OrbitError("the orbit never leaves the bore: it has no section in free flight");
  const RubFlow flow(p, w, settle_apex_m(p, s));
  const Eigen::VectorXd x = flow.physical(shoot(flow, flow.scaled(o.state), t0, t0 + middle, s, false).end);
  OrbitSettings moved = s;
  moved.section_angle_rad = std::fmod(o.section_angle_rad + w * middle, 2.0 * M_PI);
  return find_periodic_orbit(p, w, x, moved);
}

void check_range(const ContinuationSettings& settings, const ContinuationParameter& parameter, double v0) {
  const bool speed = !parameter.model;
  if (!(settings.min_speed_rad_per_s < settings.max_speed_rad_per_s) || (speed && !(v0 > 0.0)) ||
      !(v0 >= settings.min_speed_rad_per_s) || !(v0 <= settings.max_speed_rad_per_s)) {
    throw std::invalid_argument("orbit continuation: the start's " + parameter.name + " " + std::to_string(v0) +
                                " must lie in a range of some width" + (speed ? " and be above 0" : ""));
  }
}

}  // namespace

OrbitBranch continue_orbit(const ModelParameters& p, const PeriodicOrbit& start, const ContinuationSettings& settings,
                           const OrbitSettings& orbit, const ContinuationParameter& parameter, double start_value) {
  if (start.turning) {
    throw std::invalid_argument("orbit continuation: the start is periodic in the turning frame, which is not traced");
  }
  const double v0 = parameter.model ? start_value : start.speed_rad_per_s;
  check_range(settings, parameter, v0);
  OrbitSettings s = orbit;
  s.periods = start.periods;
  s.section_angle_rad = start.section_angle_rad;
  OrbitBranch branch;
  // A section in contact moves into free flight where the orbit has one.
  const bool flies =
      std::any_of(start.events.begin(), start.events.end(), [](const OrbitEvent& e) { return starts_flight(e.kind); });
  branch.points.push_back(start.starts_in_contact && flies ? free_section(p, start, s) : start);
  branch.points.front().parameter = v0;
  s.section_angle_rad = branch.points.front().section_angle_rad;
  const OrbitEquations g = OrbitEquations(p, s, parameter, v0, start.speed_rad_per_s, branch.points.front().events)
                               .at(branch.points.front());
  const Vector Y = g.unknowns(branch.points.front());
  Vector direction = Vector::Zero(Y.size());
  direction(Y.size() - 1) = settings.increasing_speed ? 1.0 : -1.0;
  try {
    trace(g, Y, g.tangent(Y, direction), settings, settings.step, branch);
  } catch (const OrbitError& e) {
    branch.end = e.what();
  }
  return branch;
}

OrbitBranch continue_period_doubled(const ModelParameters& p, const OrbitBifurcation& pd,
                                    const ContinuationSettings& settings, const OrbitSettings& orbit,
                                    const ContinuationParameter& parameter) {
  if (pd.kind != OrbitBifurcationKind::kPeriodDoubling) {
    throw std::invalid_argument("continue_period_doubled: the bifurcation is a " + std::string(to_string(pd.kind)));
  }
  check_range(settings, parameter, pd.parameter);
  const PeriodicOrbit& single = pd.orbit;
  // The multiplier's eigenvector at -1: the doubled branch leaves along it.
  const Eigen::EigenSolver<Eigen::MatrixXd> es(single.monodromy);
  int k = 0;
  for (int i = 1; i < es.eigenvalues().size(); ++i) {
    if (std::abs(es.eigenvalues()(i) + 1.0) < std::abs(es.eigenvalues()(k) + 1.0)) k = i;
  }
  // (in the coordinates of its monodromy: the tangent basis's in contact)
  const int n = static_cast<int>(single.monodromy.rows());
  Vector t0 = Vector::Zero(n + 1);
  t0.head(n) = es.eigenvectors().col(k).real().normalized();
  OrbitSettings s = orbit;
  s.periods = 2 * single.periods;
  s.section_angle_rad = single.section_angle_rad;
  // The doubled orbit's events: the single's twice (the shot of its own
  // period at the bifurcation).
  std::vector<OrbitEvent> events = single.events;
  events.insert(events.end(), single.events.begin(), single.events.end());
  const OrbitEquations g = OrbitEquations(p, s, parameter, pd.parameter, single.speed_rad_per_s, events).at(single);
  Vector Y0 = g.unknowns(single);
  OrbitBranch branch;
  try {
    Vector Y1;
    int iterations = 0;
    // The doubled orbit leaves the single one as the square root of the
    // speed's distance from the doubling: a first step of the usual length
    // would pass a doubling of its own that follows close behind (a cascade).
    double ds = kFirstDoubledStep * settings.step;
    while (!g.correct(Y0 + ds * t0, t0, Y1, iterations)) {
      ds *= 0.5;
      if (ds < kMinStep) throw OrbitError("the doubled branch's first point: the corrector fails at the smallest step");
    }
    const PeriodicOrbit first = g.orbit(Y1, iterations);
    if (halves_agree(g.model_at(pd.parameter), s, first)) {
      throw OrbitError("the corrector fell back onto the single period's orbit at the period doubling");
    }
    branch.points.push_back(first);
    Vector direction = Y1 - Y0;
    trace(g, Y1, g.tangent(Y1, direction), settings, ds, branch);
  } catch (const OrbitError& e) {
    if (branch.points.empty()) throw;
    branch.end = e.what();
  }
  return branch;
}

}  // namespace rotor_rub::core
