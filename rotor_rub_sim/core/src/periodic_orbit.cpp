#include "rotor_rub_sim/core/periodic_orbit.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <boost/numeric/odeint/external/eigen/eigen.hpp>
#include <cmath>
#include <limits>
#include <sstream>

#include "orbit_shot.hpp"
#include "rotor_rub_sim/core/event_location.hpp"

namespace rotor_rub::core {

const char* to_string(OrbitEvent::Kind kind) {
  switch (kind) {
    case OrbitEvent::Kind::kImpact:
      return "impact";
    case OrbitEvent::Kind::kTouchdown:
      return "touchdown";
    case OrbitEvent::Kind::kLiftOff:
      return "lift-off";
  }
  return "?";
}

Eigen::MatrixXd RubFlow::tangent_basis(const Eigen::VectorXd& y) const {
  Eigen::MatrixXd normals(n_, 2);
  normals.col(0) = gap_gradient(y).transpose();
  normals.col(1) = closing_rate_gradient(y).transpose();
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(normals);
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(n_, n_);
  return q.rightCols(n_ - 2);
}

namespace {

using Vector = Eigen::VectorXd;
namespace odeint = boost::numeric::odeint;
using Stepper = odeint::runge_kutta_fehlberg78<Vector, double, Vector, double, odeint::vector_space_algebra>;
using ErrorChecker = odeint::default_error_checker<double, odeint::vector_space_algebra, odeint::default_operations>;
using Controlled = odeint::controlled_runge_kutta<Stepper, ErrorChecker>;

// A start this close to the bore (in units of C), this slow across it (of
// C w) and pressed onto it is in contact: a settled run's full rub lies on
// the bore to its tolerance.
constexpr double kOnBore = 1e-8;
// A shooting residual this small (of C and C w) needs no Newton step.
constexpr double kPolished = 1e-13;
// A slip this small (in units of C w) at a contact's start is a stick.
constexpr double kStickSlip = 1e-9;
// Where a flight that starts on the bore is probed (return_to_bore), in
// fractions of the step: near the start, where it departs as a power of the
// time, and on.
constexpr double kDepartureProbes[] = {1e-3, 1e-2, 1e-1, 0.5};
// A free flight's gap above this (of C) at a step's end with no event
// found is a missed contact.
constexpr double kPenetration = 1e-9;
// The controlled stepper's shortest step in periods before the shot fails.
constexpr double kMinStepPeriods = 1e-14;

// One shot of the flow: its state, the Jacobian carried along, the regime.
struct Shot {
  Vector y;
  Eigen::MatrixXd phi;
  OrbitRegime regime = OrbitRegime::kFree;
  double slip_sign = 1.0;
  std::vector<OrbitEvent> events;
  double slowest_impact = std::numeric_limits<double>::infinity();
  double closest_miss = std::numeric_limits<double>::infinity();
};

class Shooter {
 public:
  Shooter(const RubFlow& flow, const OrbitSettings& s, bool with_jacobian)
      : flow_(flow), s_(s), jac_(with_jacobian), n_(flow.size()) {}

  // The regime a state starts in, and its slip's sign in contact.
  void start(Shot& shot, double t) const {
    shot.regime = OrbitRegime::kFree;
    if (flow_.gap(shot.y) > -kOnBore && std::abs(flow_.closing_rate(shot.y)) < kOnBore &&
        flow_.normal_force(t, shot.y) > 0.0) {
      flow_.project_to_bore(shot.y);
      enter_contact(shot, t);
    } else if (flow_.gap(shot.y) > kPenetration ||
               (flow_.gap(shot.y) > 0.0 && flow_.closing_rate(shot.y) > kGrazingVelocity)) {
      throw OrbitError("the state at t = " + std::to_string(t) +
                       " s lies inside the bore, not pressed onto it and not leaving it");
    }
    if (jac_) shot.phi = Eigen::MatrixXd::Identity(n_, n_);
  }

  void advance(Shot& shot, double t0, double t1) const {
    const double dt_max = flow_.period() / s_.min_steps_per_period;
    Controlled controlled(ErrorChecker(s_.tolerance, s_.tolerance, 1.0, 1.0));
    const std::size_t max_events =
        shot.events.size() + static_cast<std::size_t>(s_.max_events * std::ceil((t1 - t0) / flow_.period()));
    double t = t0, dt = 0.1 * dt_max;
    Vector z = pack(shot), z_new;
    auto system = [this, &shot](const Vector& zz, Vector& dzdt, double tt) { augmented(shot, zz, dzdt, tt); };
    while (t < t1) {
      dt = std::min({dt, dt_max, t1 - t});
      double t_new = t, dt_try = dt;
      z_new = z;
      if (controlled.try_step(system, z_new, t_new, dt_try) != odeint::success) {
        dt = dt_try;
        if (dt < kMinStepPeriods * flow_.period()) {
          throw OrbitError("the integrator's step collapsed at t = " + std::to_string(t) + " s");
        }
        continue;
      }
      const double t_event = find_event(shot, z, t, z_new, t_new);
      if (t_event < t_new) {
        Stepper().do_step(system, z, t, z_new, t_event - t);
        t_new = t_event;
      }
      z = z_new;
      t = t_new;
      dt = dt_try;
      if (!z.allFinite()) throw OrbitError("the state is not finite at t = " + std::to_string(t) + " s");
      unpack(z, shot);
      if (t_event == t_new) {
        jump(shot, t);
        z = pack(shot);
      }
      if (shot.events.size() > max_events) {
        throw OrbitError("more than " + std::to_string(s_.max_events) +
                         " events in a forcing period: a chattering sequence of impacts, which the shooting does not "
                         "follow");
      }
    }
  }

 private:
  Vector pack(const Shot& shot) const {
    Vector z(jac_ ? n_ + n_ * n_ : n_);
    z.head(n_) = shot.y;
    if (jac_) z.tail(n_ * n_) = Eigen::Map<const Vector>(shot.phi.data(), n_ * n_);
    return z;
  }
  void unpack(const Vector& z, Shot& shot) const {
    shot.y = z.head(n_);
    if (jac_) shot.phi = Eigen::Map<const Eigen::MatrixXd>(z.data() + n_, n_, n_);
  }
  void augmented(const Shot& shot, const Vector& z, Vector& dzdt, double t) const {
    const Vector y = z.head(n_);
    Vector f;
    flow_.field(t, y, shot.regime, shot.slip_sign, f);
    dzdt.resize(z.size());
    dzdt.head(n_) = f;
    if (jac_) {
      const Eigen::Map<const Eigen::MatrixXd> phi(z.data() + n_, n_, n_);
      Eigen::Map<Eigen::MatrixXd>(dzdt.data() + n_, n_, n_) = flow_.jacobian(t, y, shot.regime, shot.slip_sign) * phi;
    }
  }

  // The state at t in [ta, tb] of a step from za: one step of the same
  // stepper, shorter than the accepted one (no larger error).
  Vector state_at(const Shot& shot, const Vector& za, double ta, double t) const {
    if (t == ta) return za.head(n_);
    Vector y = za.head(n_), out;
    auto system = [this, &shot](const Vector& yy, Vector& dydt, double tt) {
      flow_.field(tt, yy, shot.regime, shot.slip_sign, dydt);
    };
    Stepper().do_step(system, y, ta, out, t - ta);
    return out;
  }

  // A flight that starts on the bore (a rebound, a plastic impact's
  // departure, a lift-off): its return inside the step, or +infinity. The
  // gap counted from the start's own (a rounding on the far side) over the
  // time since the start is negative while the flight is away and positive
  // once it is back inside the bore, however short the flight (the
  // switching method's deflation); it is probed nearer the start, where a
  // departure without a rate opens as a power of the time, and at a
  // rebound's apex and 1.5 times its flight by its parabola (2 |delta'| /
  // delta''), so that a flight and its return never both fall between two
  // probes
  // (ShotsFollowEveryRebound). Throws OrbitError where the flight never
  // leaves the bore yet ends the step inside it.
  double return_to_bore(const Shot& shot, const Vector& za, double ta, double ga, double tb, double gb) const {
    constexpr double kNone = std::numeric_limits<double>::infinity();
    RunStats stats;
    auto deflated = [&](double t) { return (flow_.gap(state_at(shot, za, ta, t)) - ga) / (t - ta); };
    std::vector<double> probes;
    for (const double fraction : kDepartureProbes) probes.push_back(ta + fraction * (tb - ta));
    const Vector ya = za.head(n_);
    const double rate = flow_.closing_rate(ya) * flow_.speed(), pressing = flow_.normal_force(ta, ya);
    if (rate < 0.0 && pressing > 0.0) {
      const double flight = 2.0 * -rate / (pressing * flow_.speed() * flow_.speed());
      for (const double at : {0.5 * flight, 1.5 * flight}) {  // its apex, and past its return
        if (ta + at > ta && ta + at < tb) probes.push_back(ta + at);
      }
    }
    probes.push_back(tb);
    std::sort(probes.begin(), probes.end());
    double t_away = kNone, d_away = 0.0;
    for (const double t : probes) {
      if (!(t > ta)) continue;
      const double d = t == tb ? (gb - ga) / (tb - ta) : deflated(t);
      if (d < 0.0) {
        t_away = t;
        d_away = d;
      } else if (t_away < kNone) {
        return locate_event(deflated, t_away, d_away, t, d, stats);
      }
    }
    if (t_away == kNone && gb > kPenetration) {
      throw OrbitError("the free flight stays on the bore from t = " + std::to_string(ta) +
                       " s: neither pressed onto it nor leaving it (a graze the shooting cannot resolve)");
    }
    return kNone;
  }

  // The first event in (ta, tb], or +infinity.
  double find_event(Shot& shot, const Vector& za, double ta, const Vector& zb, double tb) const {
    constexpr double kNone = std::numeric_limits<double>::infinity();
    RunStats stats;
    const Vector ya = za.head(n_), yb = zb.head(n_);
    if (shot.regime == OrbitRegime::kFree) {
      auto gap = [&](double t) { return flow_.gap(state_at(shot, za, ta, t)); };
      const double ga = flow_.gap(ya), gb = flow_.gap(yb);
      if (ga < 0.0 && gb >= 0.0) return locate_event(gap, ta, ga, tb, gb, stats);
      if (ga >= 0.0) return return_to_bore(shot, za, ta, ga, tb, gb);
      // An apex inside the step: where delta' falls through 0.
      const double ra = flow_.closing_rate(ya), rb = flow_.closing_rate(yb);
      if (ga < 0.0 && gb < 0.0 && ra > 0.0 && rb < 0.0) {
        auto falling = [&](double t) { return -flow_.closing_rate(state_at(shot, za, ta, t)); };
        const double t_apex = locate_event(falling, ta, -ra, tb, -rb, stats);
        const double g_apex = gap(t_apex);
        if (g_apex >= 0.0) return locate_event(gap, ta, ga, t_apex, g_apex, stats);
        shot.closest_miss = std::min(shot.closest_miss, -g_apex);
      }
      return kNone;
    }
    auto pull = [&](double t) { return -flow_.normal_force(t, state_at(shot, za, ta, t)); };
    const double pa = -flow_.normal_force(ta, ya), pb = -flow_.normal_force(tb, yb);
    double t_lift = kNone;
    if (pa < 0.0 && pb >= 0.0) {
      t_lift = locate_event(pull, ta, pa, tb, pb, stats);
    } else if (pa < 0.0 && pb < 0.0) {
      t_lift = locate_interior_crossing(pull, ta, pa, tb, pb, kInteriorRateStep * (tb - ta), stats);
    }
    // The slip up to the lift-off (past it the contact's field is not the flow's).
    const double t_slip = std::min(t_lift, tb);
    if (flow_.slip(t_slip, t_slip == tb ? yb : state_at(shot, za, ta, t_slip)) * shot.slip_sign <= 0.0) {
      throw OrbitError("the slip stops before t = " + std::to_string(t_slip) +
                       " s: a sticking phase (rolling), which the shooting does not follow");
    }
    return t_lift;
  }

  void enter_contact(Shot& shot, double t) const {
    const double slip = flow_.slip(t, shot.y);
    if (std::abs(slip) < kStickSlip) {
      throw OrbitError("a contact starts without slip at t = " + std::to_string(t) +
                       " s: a sticking phase (rolling), which the shooting does not follow");
    }
    shot.regime = OrbitRegime::kContact;
    shot.slip_sign = slip > 0.0 ? 1.0 : -1.0;
  }

  // The event at t: its jump, and the saltation matrix on the Jacobian.
  void jump(Shot& shot, double t) const {
    if (shot.regime == OrbitRegime::kContact) {
      // A lift-off: N = 0, the two fields agree; the saltation matrix is I.
      shot.regime = OrbitRegime::kFree;
      shot.events.push_back({OrbitEvent::Kind::kLiftOff, t, 0.0});
      return;
    }
    const Vector y = shot.y;
    const double vn = flow_.closing_rate(y);
    if (!(vn > kGrazingVelocity)) {
      std::ostringstream msg;
      msg << "the orbit grazes the bore at t = " << t << " s (closing velocity " << vn
          << " of C w): its monodromy is not defined there";
      throw OrbitError(msg.str());
    }
    shot.slowest_impact = std::min(shot.slowest_impact, vn);
    bool settles = false;
    shot.y = flow_.impact(t, y, &settles);
    const bool pressed = settles && flow_.normal_force(t, shot.y) > 0.0;
    if (pressed) enter_contact(shot, t);
    shot.events.push_back({pressed ? OrbitEvent::Kind::kTouchdown : OrbitEvent::Kind::kImpact, t,
                           vn * flow_.model().parameters().clearance_m * flow_.speed()});
    if (!jac_) return;
    Vector f_minus, f_plus;
    flow_.field(t, y, OrbitRegime::kFree, 0.0, f_minus);
    flow_.field(t, shot.y, shot.regime, shot.slip_sign, f_plus);
    const Eigen::MatrixXd g = flow_.impact_jacobian(t, y);
    const Eigen::RowVectorXd h = flow_.gap_gradient(y);
    const Eigen::MatrixXd saltation = g + (f_plus - g * f_minus) * h / h.dot(f_minus);
    shot.phi = saltation * shot.phi;
  }

  const RubFlow& flow_;
  const OrbitSettings& s_;
  bool jac_;
  int n_;
};

}  // namespace

void check_grazing(double closest_miss) {
  if (closest_miss < kGrazingGap) {
    std::ostringstream msg;
    msg << "the orbit passes within " << closest_miss
        << " of C of the bore without touching it: a grazing orbit, whose monodromy is not defined";
    throw OrbitError(msg.str());
  }
}

void check_scene(const ModelParameters& p, double w, const OrbitSettings& s) {
  if (p.drive_model != DriveModel::kPrescribed) {
    throw std::invalid_argument(
        "periodic orbits: scene key 'drive_model' is 'motor'; accepted: prescribed (a motor's spin is not periodic "
        "in the forcing's period)");
  }
  if (!(w > 0.0) || !std::isfinite(w)) {
    throw std::invalid_argument("periodic orbits: speed " + std::to_string(w) + " rad/s; accepted: (0, inf)");
  }
  if (!(s.section_angle_rad >= 0.0 && s.section_angle_rad < 2.0 * M_PI)) {
    throw std::invalid_argument("periodic orbits: section_angle_rad " + std::to_string(s.section_angle_rad) +
                                "; accepted: [0, 2 pi)");
  }
  if (s.periods < 1) {
    throw std::invalid_argument("periodic orbits: periods " + std::to_string(s.periods) + "; accepted: integer >= 1");
  }
}

std::vector<std::complex<double>> sorted_eigenvalues(const Eigen::MatrixXd& m) {
  const Eigen::EigenSolver<Eigen::MatrixXd> es(m, false);
  std::vector<std::complex<double>> out(es.eigenvalues().data(), es.eigenvalues().data() + m.rows());
  std::stable_sort(out.begin(), out.end(), [](const std::complex<double>& a, const std::complex<double>& b) {
    return std::abs(a) > std::abs(b);
  });
  return out;
}

OrbitShot shoot(const RubFlow& flow, const Eigen::VectorXd& y0, double t0, double t1, const OrbitSettings& s,
                bool with_jacobian) {
  const Shooter shooter(flow, s, with_jacobian);
  Shot shot;
  shot.y = y0;
  OrbitShot out;
  try {
    shooter.start(shot, t0);
    out.start = shot.y;
    out.starts_in_contact = shot.regime == OrbitRegime::kContact;
    shooter.advance(shot, t0, t1);
  } catch (const OrbitError&) {
    throw;
  } catch (const std::exception& e) {  // a root finder's (TOMS 748's) own error
    throw OrbitError(std::string("the event location failed: ") + e.what());
  }
  out.end = shot.y;
  out.jacobian = std::move(shot.phi);
  out.events = std::move(shot.events);
  out.ends_in_contact = shot.regime == OrbitRegime::kContact;
  out.slowest_impact = shot.slowest_impact;
  out.closest_miss = shot.closest_miss;
  return out;
}

std::vector<Eigen::VectorXd> keyphasor_states(const RubFlow& flow, const Eigen::VectorXd& y, double t0,
                                              const OrbitSettings& s) {
  const double period = flow.period();
  double t = std::ceil(t0 / period) * period;
  std::vector<Eigen::VectorXd> out;
  Eigen::VectorXd at = t == t0 ? y : shoot(flow, y, t0, t, s, false).end;
  for (int k = 0; k < s.periods; ++k, t += period) {
    out.push_back(flow.physical(at));
    if (k + 1 < s.periods) at = shoot(flow, at, t, t + period, s, false).end;
  }
  return out;
}

OrbitFlow orbit_flow(const ModelParameters& p, double w, const Eigen::VectorXd& x0, double t0, double t1,
                     const OrbitSettings& s) {
  check_scene(p, w, s);
  const RubFlow flow(p, w, settle_apex_m(p, s));
  if (x0.size() != flow.size()) {
    throw std::invalid_argument("periodic orbits: a state of " + std::to_string(x0.size()) + " entries; accepted: " +
                                std::to_string(flow.size()) + " (the free layout's for this stator)");
  }
  const OrbitShot shot = shoot(flow, flow.scaled(x0), t0, t1, s, true);
  OrbitFlow out;
  out.state = flow.physical(shot.end);
  out.jacobian = flow.physical_jacobian(shot.jacobian);
  out.events = shot.events;
  out.ends_in_contact = shot.ends_in_contact;
  out.slowest_impact = shot.slowest_impact;
  out.closest_miss = shot.closest_miss;
  return out;
}

PeriodicOrbit find_periodic_orbit(const ModelParameters& p, double w, const Eigen::VectorXd& guess,
                                  const OrbitSettings& s) {
  check_scene(p, w, s);
  const RubFlow flow(p, w, settle_apex_m(p, s));
  const int n = flow.size();
  if (guess.size() != n) {
    throw std::invalid_argument("periodic orbits: a guess of " + std::to_string(guess.size()) +
                                " entries; accepted: " + std::to_string(n));
  }
  const double period = s.periods * flow.period(), t0 = s.section_angle_rad / w;
  Vector y = flow.scaled(guess);
  bool in_contact = false;
  PeriodicOrbit orbit;
  orbit.speed_rad_per_s = w;
  orbit.parameter = w;
  orbit.period_s = period;
  orbit.periods = s.periods;
  for (int it = 0;; ++it) {
    OrbitShot shot;
    try {
      shot = shoot(flow, y, t0, t0 + period, s, true);
    } catch (const OrbitError& e) {
      if (it == 0) throw;
      throw OrbitError("no periodic orbit near the guess: Newton's iterate " + std::to_string(it) + ": " + e.what());
    }
    if (it == 0) in_contact = shot.starts_in_contact;
    if (shot.starts_in_contact != in_contact) {
      throw OrbitError("Newton's iterate left the start's regime: no orbit near the guess");
    }
    y = shot.start;  // projected onto the bore in contact
    if (shot.ends_in_contact != in_contact) {
      throw OrbitError(std::string("the shot ends ") + (in_contact ? "in free flight" : "in contact") +
                       " where it started " + (in_contact ? "in contact" : "in free flight") +
                       ": no orbit near the guess");
    }
    const Vector r = shot.end - y;
    const double residual = r.lpNorm<Eigen::Infinity>();
    const Eigen::MatrixXd basis = in_contact ? flow.tangent_basis(y) : Eigen::MatrixXd::Identity(n, n);
    const Eigen::MatrixXd m = basis.transpose() * shot.jacobian * basis;
    // Accepted below the tolerance, after at least one Newton step unless
    // already at the rounding (a settled start meets the tolerance as it is).
    if (residual < s.newton_tolerance && (it > 0 || residual < kPolished)) {
      orbit.starts_in_contact = in_contact;
      orbit.section_angle_rad = s.section_angle_rad;
      orbit.state = flow.physical(y);
      orbit.keyphasor_states = keyphasor_states(flow, y, t0, s);
      orbit.events = shot.events;
      orbit.monodromy = m;
      orbit.tangent_basis = basis;
      orbit.multipliers = sorted_eigenvalues(m);
      orbit.newton_iterations = it;
      orbit.residual = residual;
      orbit.slowest_impact = shot.slowest_impact;
      orbit.closest_miss = shot.closest_miss;
      check_grazing(orbit.closest_miss);
      return orbit;
    }
    if (it >= s.max_newton_iterations || !std::isfinite(residual)) {
      std::ostringstream msg;
      msg << "no periodic orbit near the guess: Newton's residual is " << residual << " of C after " << it
          << " iterations";
      throw OrbitError(msg.str());
    }
    const Eigen::MatrixXd a = m - Eigen::MatrixXd::Identity(m.rows(), m.cols());
    y += basis * a.fullPivLu().solve(-(basis.transpose() * r));
    if (in_contact) flow.project_to_bore(y);
  }
}

Eigen::VectorXd settled_state(const ModelParameters& p, double w, int periods, const OrbitSettings& s) {
  check_scene(p, w, s);
  const RubFlow flow(p, w, settle_apex_m(p, s));
  const StationModel& station = flow.model();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(flow.size());
  const Kinematics rest = station.initial_kinematics();
  x.head<2>() = rest.rotor_pos + station.frame_shift();
  if (flow.size() == 8) x.segment<2>(2) = rest.stator_pos;
  const double t1 = periods * flow.period() + s.section_angle_rad / w;
  return flow.physical(shoot(flow, flow.scaled(x), 0.0, t1, s, false).end);
}

}  // namespace rotor_rub::core
