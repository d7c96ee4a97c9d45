// The event-driven shot of the Jeffcott's flow with its variational
// equations and saltation matrices (orbit_shot.hpp): the phases' fields,
// the events' location and jumps; periodic_orbit.cpp, turning_orbit.cpp and
// orbit_continuation.cpp build on it.
#include "orbit_shot.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <boost/numeric/odeint/external/eigen/eigen.hpp>
#include <cmath>
#include <limits>
#include <sstream>

#include "methods/event_scanner.hpp"

namespace rotor_rub::core {

Eigen::MatrixXd RubFlow::tangent_basis(double t, const Eigen::VectorXd& y, bool stick) const {
  const int m = stick ? 3 : 2;
  Eigen::MatrixXd normals(n_, m);
  normals.col(0) = gap_gradient(y).transpose();
  normals.col(1) = closing_rate_gradient(y).transpose();
  if (stick) normals.col(2) = slip_gradient(t, y).transpose();
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(normals);
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(n_, n_);
  return q.rightCols(n_ - m);
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
  // In contact, the event find_event located: kLiftOff, kStick (the slip
  // stops: jump() decides stick or reversal) or kSlip (a breakaway).
  OrbitEvent::Kind pending = OrbitEvent::Kind::kLiftOff;
  // The step after an event that starts a flight from the bore (departing)
  // or a slip from rest (slip_from_rest): its function starts at a
  // rounding, so its first return is sought, not a crossing.
  bool departing = false, slip_from_rest = false;
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
      // A held contact's events carry the unbalance at its angle in the
      // contact frame, phi - psi: a step turns it by at most
      // kMaxScanAngle_rad (event_scanner.hpp), as in the methods.
      const double dt_held = shot.regime == OrbitRegime::kFree
                                 ? dt_max
                                 : kMaxScanAngle_rad / (flow_.speed() + std::abs(flow_.angle_rate(shot.y)));
      dt = std::min({dt, dt_max, dt_held, t1 - t});
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
      if (shot.regime != OrbitRegime::kFree && t_event != t_new) {
        // A held phase is integrated in the plane, which keeps its
        // constraints (delta = C, delta' = 0; v_slide = 0 in a stick) only
        // to the tolerance: each step ends projected back onto them (a move
        // of the step's error), so that a long rolling stays on the bore
        // (OrbitsCli.StickingOrbits' dry whip); but for a step to an event,
        // whose departure the event's own rates decide (a lift-off's flight
        // opens as a power of the time).
        flow_.project_to_bore(shot.y);
        if (shot.regime == OrbitRegime::kStick) flow_.project_to_stick(t, shot.y);
        z.head(n_) = shot.y;
      }
      shot.departing = shot.slip_from_rest = false;
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

  // The first time in (ta, tb] where g, at ga at a boundary at ta (a flight
  // that starts on the bore; a slip that starts from rest: a breakaway, a
  // reversal, a contact that starts at rest), comes back
  // through it, or +infinity: g counted from ga over the time since ta is
  // negative while g is away and positive once it is back, however short
  // the excursion (the switching method's deflation). Probed at the
  // fractions kDepartureProbes of the step, where a departure without a
  // rate opens as a power of the time, at `extra` and at tb (g(tb) = gb);
  // *away: whether a probe found g away.
  template <class G>
  double first_return(G&& g, double ta, double ga, double tb, double gb, const std::vector<double>& extra,
                      bool* away) const {
    constexpr double kNone = std::numeric_limits<double>::infinity();
    RunStats stats;
    auto deflated = [&](double t) { return (g(t) - ga) / (t - ta); };
    std::vector<double> probes = extra;
    for (const double fraction : kDepartureProbes) probes.push_back(ta + fraction * (tb - ta));
    probes.push_back(tb);
    std::sort(probes.begin(), probes.end());
    double t_away = kNone, d_away = 0.0;
    for (const double t : probes) {
      if (!(t > ta) || t > tb) continue;
      const double d = t == tb ? (gb - ga) / (tb - ta) : deflated(t);
      if (d < 0.0) {
        t_away = t;
        d_away = d;
      } else if (t_away < kNone) {
        return locate_event(deflated, t_away, d_away, t, d, stats);
      }
    }
    if (away != nullptr) *away = t_away < kNone;
    return kNone;
  }

  // A flight that starts on the bore (a rebound, a plastic impact's
  // departure, a lift-off): its return inside the step, or +infinity, by
  // first_return on the gap, probed too at a rebound's apex and 1.5 times
  // its flight by its parabola (2 |delta'| / delta''), so that a flight and
  // its return never both fall between two probes
  // (ShotsFollowEveryRebound). Throws OrbitError where the flight never
  // leaves the bore yet ends the step inside it.
  double return_to_bore(const Shot& shot, const Vector& za, double ta, double ga, double tb, double gb) const {
    std::vector<double> probes;
    const Vector ya = za.head(n_);
    const double rate = flow_.closing_rate(ya) * flow_.speed(), pressing = flow_.normal_force(ta, ya);
    if (rate < 0.0 && pressing > 0.0) {
      const double flight = 2.0 * -rate / (pressing * flow_.speed() * flow_.speed());
      for (const double at : {0.5 * flight, 1.5 * flight}) {  // its apex, and past its return
        if (ta + at > ta && ta + at < tb) probes.push_back(ta + at);
      }
    }
    bool away = false;
    const double t =
        first_return([&](double tt) { return flow_.gap(state_at(shot, za, ta, tt)); }, ta, ga, tb, gb, probes, &away);
    if (t == std::numeric_limits<double>::infinity() && !away && gb > kPenetration) {
      throw OrbitError("the free flight stays on the bore from t = " + std::to_string(ta) +
                       " s: neither pressed onto it nor leaving it (a graze the shooting cannot resolve)");
    }
    return t;
  }

  // g's first root in (ta, tb] from below: a crossing at the step's end, or
  // within it and back (an interior maximum); +infinity without.
  template <class G>
  static double crossing(G&& g, double ta, double ga, double tb, double gb) {
    RunStats stats;
    EventWatch w;  // the methods' scan (event_scanner.hpp), every function armed
    w.armed = true;
    return core::crossing(w, g, ta, ga, tb, gb, stats);
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
      // A flight that starts on the bore (a departure, whose closing rate
      // at ta is a rounding, no apex).
      if (ga >= 0.0 || shot.departing) {
        return return_to_bore(shot, za, ta, ga, tb, gb);
      }
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
    const double t_lift = crossing(pull, ta, -flow_.normal_force(ta, ya), tb, -flow_.normal_force(tb, yb));
    if (shot.regime == OrbitRegime::kStick) {
      // A breakaway: the stick force leaves the cone, which closes as N
      // falls (a lift-off from a stick needs the stick force to vanish
      // with N: then the two fields agree too).
      auto leaving = [&](double t) { return -flow_.cone_margin(t, state_at(shot, za, ta, t)); };
      const double t_break = crossing(leaving, ta, -flow_.cone_margin(ta, ya), tb, -flow_.cone_margin(tb, yb));
      shot.pending = t_break <= t_lift ? OrbitEvent::Kind::kSlip : OrbitEvent::Kind::kLiftOff;
      return std::min(t_break, t_lift);
    }
    // The slip's stop: v_slide s falling through 0; from a slip that starts
    // at rest (a breakaway, a stick's cone refused at a contact's start) its
    // first return. Without friction the slip's sign is no event.
    if (!(flow_.model().parameters().friction_coefficient > 0.0)) {
      shot.pending = OrbitEvent::Kind::kLiftOff;
      return t_lift;
    }
    auto stopping = [&](double t) { return -shot.slip_sign * flow_.slip(t, state_at(shot, za, ta, t)); };
    const double sa = -shot.slip_sign * flow_.slip(ta, ya), sb = -shot.slip_sign * flow_.slip(tb, yb);
    if (!shot.slip_from_rest && !(sa < 0.0)) {
      throw OrbitError("the slip at t = " + std::to_string(ta) +
                       " s runs against its friction's sign: a stop the shooting missed");
    }
    const double t_stop =
        shot.slip_from_rest ? first_return(stopping, ta, sa, tb, sb, {}, nullptr) : crossing(stopping, ta, sa, tb, sb);
    shot.pending = t_stop < t_lift ? OrbitEvent::Kind::kStick : OrbitEvent::Kind::kLiftOff;
    return std::min(t_stop, t_lift);
  }

  // The contact's friction regime at its start (a touchdown, a state on the
  // bore): sliding the slip's way, or from rest sticking where the cone
  // holds the stick force (the slip then set to exactly 0), else sliding
  // against it (contact_law.hpp's select_friction_mode).
  void enter_contact(Shot& shot, double t) const {
    const double slip = flow_.slip(t, shot.y);
    shot.regime = OrbitRegime::kContact;
    if (std::abs(slip) >= kStickSlip) {
      shot.slip_sign = slip > 0.0 ? 1.0 : -1.0;
      return;
    }
    const FrictionMode mode = rest_mode(shot, t);
    shot.slip_sign = mode.slip_sign;
    shot.slip_from_rest = !mode.stick;
    if (mode.stick) {
      shot.regime = OrbitRegime::kStick;
      flow_.project_to_stick(t, shot.y);
    }
  }
  // The friction mode of a contact at rest (v_slide = 0) at t; OrbitError
  // at the cone's edge.
  FrictionMode rest_mode(const Shot& shot, double t) const {
    const double cone = flow_.model().parameters().friction_coefficient * flow_.normal_force(t, shot.y);
    const double stick = flow_.stick_force(t, shot.y);
    if (cone > 0.0 && std::abs(cone - std::abs(stick)) < kConeEdge * cone) {
      std::ostringstream msg;
      msg << "the slip stops at t = " << t << " s at the edge of the friction cone (stick force " << stick
          << " against the cone " << cone << " of m C w^2): whether the contact sticks parts by a rounding";
      throw OrbitError(msg.str());
    }
    return select_friction_mode(0.0, true, stick, cone);
  }

  // The slip stopping at t: a stick where the cone holds the stick force,
  // else the slip reversed. No jump; the friction's switch has the
  // saltation S = I + (f+ - f-) h_x / (h_x f-), h = v_slide (Filippov's
  // crossing, and entering his sliding mode for a stick). v_slide has no
  // time of its own at a constant speed (h_t = 0), as the gap; N and the
  // cone's margin have, but at their events f+ = f-.
  void slip_stops(Shot& shot, double t) const {
    const Eigen::RowVectorXd h = flow_.slip_gradient(t, shot.y);
    Vector f_minus, f_plus;
    flow_.field(t, shot.y, shot.regime, shot.slip_sign, f_minus);
    const double rate = h.dot(f_minus);  // v_slide' / (C w)
    if (!(std::abs(rate) > kGrazingVelocity * flow_.speed())) {
      std::ostringstream msg;
      msg << "the slip comes to rest tangentially at t = " << t << " s (v_slide' " << rate / flow_.speed()
          << " of C w^2): its monodromy is not defined there";
      throw OrbitError(msg.str());
    }
    const FrictionMode mode = rest_mode(shot, t);
    shot.events.push_back({mode.stick ? OrbitEvent::Kind::kStick : OrbitEvent::Kind::kReversal, t, 0.0});
    shot.slip_sign = mode.slip_sign;
    shot.slip_from_rest = !mode.stick;
    if (mode.stick) {
      shot.regime = OrbitRegime::kStick;
      flow_.project_to_stick(t, shot.y);
    }
    if (!jac_) return;
    flow_.field(t, shot.y, shot.regime, shot.slip_sign, f_plus);
    shot.phi = (Eigen::MatrixXd::Identity(n_, n_) + (f_plus - f_minus) * h / rate) * shot.phi;
  }

  // The event at t: its jump, and the saltation matrix on the Jacobian.
  void jump(Shot& shot, double t) const {
    if (shot.regime != OrbitRegime::kFree) {
      if (shot.pending == OrbitEvent::Kind::kStick) return slip_stops(shot, t);
      // A lift-off (N = 0) or a breakaway (the stick force at f N): the two
      // fields agree; the saltation matrix is I.
      if (shot.pending == OrbitEvent::Kind::kSlip) {
        shot.regime = OrbitRegime::kContact;
        shot.slip_sign = flow_.stick_force(t, shot.y) > 0.0 ? -1.0 : 1.0;
        shot.slip_from_rest = true;
      } else {
        shot.regime = OrbitRegime::kFree;
        shot.departing = true;
      }
      shot.events.push_back({shot.pending, t, 0.0});
      return;
    }
    const Vector y = shot.y;
    const double vn = flow_.closing_rate(y);
    // A graze has no saltation matrix (it divides by vn); a shot without
    // the Jacobian (a settling run, the keyphasor's states) goes on through
    // it as the switching method does: a touch that does not close is no
    // impact.
    if (!(vn > kGrazingVelocity) && jac_) {
      std::ostringstream msg;
      msg << "the orbit grazes the bore at t = " << t << " s (closing velocity " << vn
          << " of C w): its monodromy is not defined there";
      throw OrbitError(msg.str());
    }
    if (!(vn > 0.0)) return;
    shot.slowest_impact = std::min(shot.slowest_impact, vn);
    bool settles = false;
    shot.y = flow_.impact(t, y, &settles);
    const bool pressed = settles && flow_.normal_force(t, shot.y) > 0.0;
    if (pressed) enter_contact(shot, t);
    shot.departing = !pressed;
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
    out.starts_in_contact = shot.regime != OrbitRegime::kFree;
    out.starts_in_stick = shot.regime == OrbitRegime::kStick;
    shooter.advance(shot, t0, t1);
  } catch (const OrbitError&) {
    throw;
  } catch (const std::exception& e) {  // a root finder's (TOMS 748's) own error
    throw OrbitError(std::string("the event location failed: ") + e.what());
  }
  out.end = shot.y;
  out.jacobian = std::move(shot.phi);
  out.events = std::move(shot.events);
  out.ends_in_contact = shot.regime != OrbitRegime::kFree;
  out.ends_in_stick = shot.regime == OrbitRegime::kStick;
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

}  // namespace rotor_rub::core
