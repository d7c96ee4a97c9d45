#include "rotor_rub_sim/core/response_class.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

namespace rotor_rub::core {
namespace {

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  double ma = 0.0, mb = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ma += a[i] / n;
    mb += b[i] / n;
  }
  double sab = 0.0, saa = 0.0, sbb = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  if (saa <= 0.0 || sbb <= 0.0) return 0.0;  // a constant series: no growth
  return sab / std::sqrt(saa * sbb);
}

}  // namespace

// No default labels: -Werror=switch names a value added without a name. The
// throw after each switch is for a value cast from an integer out of range.
const char* to_string(ContactKind v) {
  switch (v) {
    case ContactKind::kNone:
      return "none";
    case ContactKind::kPartial:
      return "partial";
    case ContactKind::kFull:
      return "full";
  }
  throw std::logic_error("to_string: not a ContactKind");
}

const char* to_string(Motion v) {
  switch (v) {
    case Motion::kPeriodic:
      return "periodic";
    case Motion::kQuasiPeriodic:
      return "quasi_periodic";
    case Motion::kChaotic:
      return "chaotic";
    case Motion::kAperiodic:
      return "aperiodic";
    case Motion::kTooShort:
      return "too_short";
  }
  throw std::logic_error("to_string: not a Motion");
}

const char* to_string(Whirl v) {
  switch (v) {
    case Whirl::kForward:
      return "forward";
    case Whirl::kBackward:
      return "backward";
  }
  throw std::logic_error("to_string: not a Whirl");
}

const char* to_string(ResponseClass v) {
  switch (v) {
    case ResponseClass::kNoContact:
      return "no_contact";
    case ResponseClass::kFullRub:
      return "full_rub";
    case ResponseClass::kPartialRub:
      return "partial_rub";
    case ResponseClass::kQuasiPeriodic:
      return "quasi_periodic";
    case ResponseClass::kChaotic:
      return "chaotic";
    case ResponseClass::kAperiodicRub:
      return "aperiodic_rub";
    case ResponseClass::kBackwardWhirl:
      return "backward_whirl";
  }
  throw std::logic_error("to_string: not a ResponseClass");
}

void ResponseWindow::add_sample(const Sample& s) {
  ++samples;
  if (s.in_contact) ++samples_in_contact;
  const Vec2& r = s.kin.rotor_pos;
  const Vec2& v = s.kin.rotor_vel;
  whirl_moment_sum += r.x() * v.y() - r.y() * v.x();
  const double rel = (s.kin.rotor_pos - s.kin.stator_pos).norm();
  max_relative_m = std::max(max_relative_m, rel);
  min_relative_m = std::min(min_relative_m, rel);
  normal_force_sum_N += s.normal_force_N;
}

void ResponseWindow::add_point(const Sample& s) {
  points.push_back(
      {s.t_s, s.drive.speed_rad_per_s, s.kin.rotor_pos - s.kin.stator_pos, s.in_contact, s.normal_force_N});
}

double zero_one_test_k(const std::vector<double>& phi) {
  const std::size_t n_total = phi.size();
  const std::size_t n_cut = n_total / 10;
  // Too short to see growth; or absurdly long (the bound also tells GCC the
  // buffers below have a sane size).
  if (n_cut < 2 || n_total > (std::size_t{1} << 28)) return std::numeric_limits<double>::quiet_NaN();
  double mean = 0.0;
  for (double x : phi) mean += x / static_cast<double>(n_total);
  std::mt19937 rng(20261123);  // fixed: the same series gives the same K
  std::uniform_real_distribution<double> pick(M_PI / 5.0, 4.0 * M_PI / 5.0);
  std::vector<double> ks;
  std::vector<double> p(n_total + 1), q(n_total + 1), xi(n_cut), d(n_cut);
  for (int trial = 0; trial < 32; ++trial) {
    const double c = pick(rng);
    p[0] = q[0] = 0.0;
    for (std::size_t j = 0; j < n_total; ++j) {
      p[j + 1] = p[j] + phi[j] * std::cos(static_cast<double>(j + 1) * c);
      q[j + 1] = q[j] + phi[j] * std::sin(static_cast<double>(j + 1) * c);
    }
    for (std::size_t n = 1; n <= n_cut; ++n) {
      double m = 0.0;
      const std::size_t count = n_total - n_cut;
      for (std::size_t j = 1; j <= count; ++j) {
        const double dp = p[j + n] - p[j], dq = q[j + n] - q[j];
        m += (dp * dp + dq * dq) / static_cast<double>(count);
      }
      // The modified mean square displacement: without the oscillating term
      // that a nonzero mean adds (it would blur K for short series).
      const double v_osc = mean * mean * (1.0 - std::cos(static_cast<double>(n) * c)) / (1.0 - std::cos(c));
      xi[n - 1] = static_cast<double>(n);
      d[n - 1] = m - v_osc;
    }
    ks.push_back(correlation(xi, d));
  }
  std::nth_element(ks.begin(), ks.begin() + static_cast<long>(ks.size() / 2), ks.end());
  return ks[ks.size() / 2];
}

ResponseClassification classify_response(const ResponseWindow& w, double clearance_m) {
  ResponseClassification c;
  c.contact_fraction = w.samples ? static_cast<double>(w.samples_in_contact) / static_cast<double>(w.samples) : 0.0;
  c.mean_normal_force_N = w.samples ? w.normal_force_sum_N / static_cast<double>(w.samples) : 0.0;
  c.contact = w.samples_in_contact == 0 && w.contact_events == 0           ? ContactKind::kNone
              : w.samples_in_contact == w.samples && w.contact_events == 0 ? ContactKind::kFull
                                                                           : ContactKind::kPartial;
  c.whirl = w.whirl_moment_sum < 0.0 ? Whirl::kBackward : Whirl::kForward;

  const double tol = kPeriodTolerance * clearance_m;
  const auto& p = w.points;
  const int m = static_cast<int>(p.size());
  // Distinct points, up to 64 (a count, not a clustering: the first point of
  // each group of points within the tolerance).
  std::vector<Vec2> distinct;
  for (const auto& x : p) {
    bool seen = false;
    for (const auto& d : distinct) seen = seen || (x.relative_m - d).norm() <= tol;
    if (!seen && distinct.size() < 64) distinct.push_back(x.relative_m);
  }
  c.distinct_points = static_cast<int>(distinct.size());
  c.k01 = std::numeric_limits<double>::quiet_NaN();
  if (m >= kMinPoints) {
    for (int n = 1; n <= kMaxPeriod && c.period == 0; ++n) {
      // Period n is seen only with kMinComparisons comparisons at least
      // (16 points hold no second difference of period 8).
      const int span = (w.drifting ? 2 : 1) * n;
      if (m - span < kMinComparisons) break;
      bool repeats = true;
      for (int j = 0; j + span < m && repeats; ++j) {
        const Vec2 d = w.drifting ? Vec2(p[j + 2 * n].relative_m - 2.0 * p[j + n].relative_m + p[j].relative_m)
                                  : Vec2(p[j + n].relative_m - p[j].relative_m);
        repeats = d.norm() <= tol;
      }
      if (repeats) c.period = n;
    }
    if (c.period > 0) {
      c.motion = Motion::kPeriodic;
    } else {
      std::vector<double> phi;
      for (const auto& x : p) phi.push_back(x.relative_m.norm());
      if (w.drifting) {  // less the least-squares line through (j, phi_j)
        const double n = static_cast<double>(m), mean_j = 0.5 * (n - 1.0);
        double mean_phi = 0.0, sjj = 0.0, sjp = 0.0;
        for (int j = 0; j < m; ++j) mean_phi += phi[j] / n;
        for (int j = 0; j < m; ++j) {
          sjj += (j - mean_j) * (j - mean_j);
          sjp += (j - mean_j) * (phi[j] - mean_phi);
        }
        for (int j = 0; j < m; ++j) phi[j] -= mean_phi + sjp / sjj * (j - mean_j);
      }
      if (m >= kMinPointsZeroOne) {
        c.k01 = zero_one_test_k(phi);
        c.motion = c.k01 >= kChaosK ? Motion::kChaotic : Motion::kQuasiPeriodic;
      } else {
        c.motion = Motion::kAperiodic;
      }
    }
  }
  if (c.contact == ContactKind::kNone) {
    c.response = ResponseClass::kNoContact;
  } else if (c.whirl == Whirl::kBackward) {
    c.response = ResponseClass::kBackwardWhirl;
  } else if (c.contact == ContactKind::kFull) {
    c.response = ResponseClass::kFullRub;
  } else if (c.motion == Motion::kChaotic) {
    c.response = ResponseClass::kChaotic;
  } else if (c.motion == Motion::kQuasiPeriodic) {
    c.response = ResponseClass::kQuasiPeriodic;
  } else if (c.motion == Motion::kAperiodic || c.motion == Motion::kTooShort) {
    c.response = ResponseClass::kAperiodicRub;
  } else {
    c.response = ResponseClass::kPartialRub;
  }
  return c;
}

}  // namespace rotor_rub::core
