#include "rotor_rub_sim/core/turning_orbit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "orbit_shot.hpp"

namespace rotor_rub::core {

namespace {

using Vector = Eigen::VectorXd;

// Two impacts' closing velocities this close (relative) are the same
// impact of a repeating sequence: a settled orbit repeats them to its
// integration's tolerance (1e-11), a motion still drifting or quasi-periodic
// in the turning frame differs by far more.
constexpr double kSameImpact = 1e-6;
// The impacts compared before a sequence is called repeating.
constexpr int kRepeats = 4;
// A turning-frame field this small against w |y| is an equilibrium there,
// which has no section across the flow.
constexpr double kEquilibrium = 1e-9;

// y with each planar pair (positions, velocities; the rotor's and the
// stator's) turned by a.
Vector turned(const Vector& y, double a) {
  const double c = std::cos(a), s = std::sin(a);
  Vector out = y;
  for (int i = 0; i + 1 < y.size(); i += 2) {
    out(i) = c * y(i) - s * y(i + 1);
    out(i + 1) = s * y(i) + c * y(i + 1);
  }
  return out;
}
Eigen::MatrixXd turn_matrix(int n, double a) {
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) r.col(i) = turned(Vector::Unit(n, i), a);
  return r;
}

// The turning frame's field at (t, y) in free flight, f - w J y (J turning
// each pair by +90 deg), in RubFlow's units.
Vector turning_field(const RubFlow& flow, double t, const Vector& y) {
  Vector f;
  flow.field(t, y, OrbitRegime::kFree, 0.0, f);
  return f - flow.speed() * turned(y, 0.5 * M_PI);
}

}  // namespace

void check_turning_scene(const ModelParameters& p, double w, const OrbitSettings& s) {
  check_scene(p, w, s);
  auto refuse = [](const char* key, double value) {
    std::ostringstream msg;
    msg << "turning-frame orbits: scene key '" << key << "' is " << value
        << "; accepted: 0 (the scene is autonomous in the frame turning with the shaft only without gravity and "
           "with its stator centred)";
    throw std::invalid_argument(msg.str());
  };
  if (p.gravity_m_per_s2 != 0.0) refuse("gravity_m_per_s2", p.gravity_m_per_s2);
  if (p.stator_offset_x_m != 0.0) refuse("stator_offset_x_m", p.stator_offset_x_m);
  if (p.stator_offset_y_m != 0.0) refuse("stator_offset_y_m", p.stator_offset_y_m);
}

TurningGuess turning_orbit_guess(const ModelParameters& p, double w, const Eigen::VectorXd& x, double t_s, int periods,
                                 const OrbitSettings& s) {
  check_turning_scene(p, w, s);
  const RubFlow flow(p, w, settle_apex_m(p, s));
  if (x.size() != flow.size() || periods < 1) {
    throw std::invalid_argument("turning-frame orbits: a state of " + std::to_string(x.size()) + " entries over " +
                                std::to_string(periods) + " periods; accepted: " + std::to_string(flow.size()) +
                                " entries, periods >= 1");
  }
  const OrbitShot shot = shoot(flow, flow.scaled(x), t_s, t_s + periods * flow.period(), s, false);
  const std::vector<OrbitEvent>& e = shot.events;
  std::vector<std::size_t> impacts;
  for (std::size_t i = 0; i < e.size(); ++i) {
    if (is_impact(e[i].kind)) impacts.push_back(i);
  }
  // The last impacts, the most settled, against those m before them (all m
  // of them, at least kRepeats).
  const std::size_t count = impacts.size();
  auto velocity = [&](std::size_t k) { return e[impacts[count - 1 - k]].normal_velocity_m_per_s; };
  std::size_t m = 0;
  for (std::size_t j = 1; j + std::max<std::size_t>(kRepeats, j) <= count && m == 0; ++j) {
    bool same = true;
    for (std::size_t k = 0; k < std::max<std::size_t>(kRepeats, j) && same; ++k) {
      same = std::abs(velocity(k + j) - velocity(k)) <= kSameImpact * velocity(k);
    }
    if (same) m = j;
  }
  if (m == 0) {
    throw OrbitError("the motion's " + std::to_string(count) + " impacts in " + std::to_string(periods) +
                     " forcing periods do not repeat: not settled on an orbit of the turning frame (or without "
                     "impacts)");
  }
  // The longest flight among the orbit's last m impacts: its middle is the
  // section.
  const std::size_t first = impacts[count - 1 - m], last = impacts[count - 1];
  double best = -1.0, middle = 0.0;
  for (std::size_t i = first; i < last; ++i) {
    if (!starts_flight(e[i].kind)) continue;
    if (e[i + 1].time_s - e[i].time_s > best) {
      best = e[i + 1].time_s - e[i].time_s;
      middle = 0.5 * (e[i].time_s + e[i + 1].time_s);
    }
  }
  if (best < 0.0) throw OrbitError("the orbit never leaves the bore: its section must lie in free flight");
  TurningGuess guess;
  guess.time_s = middle;
  guess.period_s = e[last].time_s - e[first].time_s;
  guess.state = flow.physical(shoot(flow, flow.scaled(x), t_s, middle, s, false).end);
  return guess;
}

PeriodicOrbit find_turning_orbit(const ModelParameters& p, double w, const TurningGuess& guess,
                                 const OrbitSettings& s) {
  check_turning_scene(p, w, s);
  const RubFlow flow(p, w, settle_apex_m(p, s));
  const int n = flow.size();
  if (guess.state.size() != n || !(guess.period_s > 0.0) || !std::isfinite(guess.period_s)) {
    throw std::invalid_argument("turning-frame orbits: a guess of " + std::to_string(guess.state.size()) +
                                " entries and period " + std::to_string(guess.period_s) +
                                " s; accepted: " + std::to_string(n) + " entries, a period in (0, inf)");
  }
  // The section at the guess's spin angle in [0, 2 pi): the same forcing,
  // so the same state.
  double angle = std::fmod(w * guess.time_s, 2.0 * M_PI);
  if (angle < 0.0) angle += 2.0 * M_PI;
  const double t0 = angle / w;
  const Vector y_g = flow.scaled(guess.state);
  const Vector normal = turning_field(flow, t0, y_g);
  if (!(normal.norm() > kEquilibrium * flow.speed() * y_g.norm())) {
    throw OrbitError(
        "the guess is at rest in the turning frame (the full rub or the synchronous whirl: an equilibrium there, "
        "full_rub_stability's or steady_response's), not on a periodic orbit of it");
  }
  Vector y = y_g;
  double period = guess.period_s;
  for (int it = 0;; ++it) {
    OrbitShot shot;
    try {
      shot = shoot(flow, y, t0, t0 + period, s, true);
    } catch (const OrbitError& e) {
      if (it == 0) throw;
      throw OrbitError("no turning-frame orbit near the guess: Newton's iterate " + std::to_string(it) + ": " +
                       e.what());
    }
    if (shot.starts_in_contact || shot.ends_in_contact) {
      throw OrbitError("the turning-frame orbit's section lies in a contact: it must lie in free flight");
    }
    const Eigen::MatrixXd back = turn_matrix(n, -w * period);
    const Vector r = back * shot.end - y;
    const double residual = r.lpNorm<Eigen::Infinity>();
    if (residual < s.newton_tolerance && (it > 0 || residual < kPolished)) {
      PeriodicOrbit orbit;
      orbit.turning = true;
      orbit.speed_rad_per_s = w;
      orbit.parameter = w;
      orbit.period_s = period;
      orbit.section_angle_rad = angle;
      orbit.state = flow.physical(y);
      orbit.events = shot.events;
      orbit.monodromy = back * shot.jacobian;
      orbit.tangent_basis = Eigen::MatrixXd::Identity(n, n);
      // M f = f (f the turning frame's field at the orbit): the trivial
      // multiplier. The others are the section's map's, (I - f f^T / |f|^2)
      // M on the hyperplane across f: M's with the trivial one deflated.
      const Vector f = turning_field(flow, t0, y);
      const Eigen::MatrixXd f_column = f;
      const Eigen::HouseholderQR<Eigen::MatrixXd> qr(f_column);
      const Eigen::MatrixXd across = (qr.householderQ() * Eigen::MatrixXd::Identity(n, n)).rightCols(n - 1);
      const Eigen::MatrixXd onto = Eigen::MatrixXd::Identity(n, n) - f * f.transpose() / f.squaredNorm();
      orbit.trivial_multiplier = f.dot(orbit.monodromy * f) / f.squaredNorm();
      orbit.multipliers = sorted_eigenvalues(across.transpose() * onto * orbit.monodromy * across);
      finish_orbit(orbit, shot, it, residual);
      return orbit;
    }
    check_newton("turning-frame orbit", it, s.max_newton_iterations, residual);
    Eigen::MatrixXd a(n + 1, n + 1);
    a.topLeftCorner(n, n) = back * shot.jacobian - Eigen::MatrixXd::Identity(n, n);
    a.topRightCorner(n, 1) = back * turning_field(flow, t0 + period, shot.end);
    a.bottomLeftCorner(1, n) = normal.transpose();
    a(n, n) = 0.0;
    Vector rhs(n + 1);
    rhs.head(n) = -r;
    rhs(n) = -normal.dot(y - y_g);
    const Vector d = a.fullPivLu().solve(rhs);
    y += d.head(n);
    period += d(n);
    if (!(period > 0.0)) throw OrbitError("Newton's period is not positive: no turning-frame orbit near the guess");
  }
}

}  // namespace rotor_rub::core
