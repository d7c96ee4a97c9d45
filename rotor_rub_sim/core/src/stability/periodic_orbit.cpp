#include "rotor_rub_sim/core/periodic_orbit.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <sstream>

#include "orbit_shot.hpp"

namespace rotor_rub::core {

using Vector = Eigen::VectorXd;

const char* to_string(OrbitEvent::Kind kind) {
  switch (kind) {
    case OrbitEvent::Kind::kImpact:
      return "impact";
    case OrbitEvent::Kind::kTouchdown:
      return "touchdown";
    case OrbitEvent::Kind::kLiftOff:
      return "lift-off";
    case OrbitEvent::Kind::kStick:
      return "stick";
    case OrbitEvent::Kind::kReversal:
      return "reversal";
    case OrbitEvent::Kind::kSlip:
      return "slip";
  }
  return "?";
}

void check_grazing(double closest_miss) {
  if (closest_miss < kGrazingGap) {
    std::ostringstream msg;
    msg << "the orbit passes within " << closest_miss
        << " of C of the bore without touching it: a grazing orbit, whose monodromy is not defined";
    throw OrbitError(msg.str());
  }
}

void check_newton(const char* what, int iterations, int max_iterations, double residual) {
  if (iterations >= max_iterations || !std::isfinite(residual)) {
    std::ostringstream msg;
    msg << "no " << what << " near the guess: Newton's residual is " << residual << " of C after " << iterations
        << " iterations";
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
  // The start's regime: free (0), in contact sliding (1), sticking (2).
  const auto regime = [](bool contact, bool stick) { return stick ? 2 : contact ? 1 : 0; };
  const char* const kRegimes[] = {"in free flight", "in contact sliding", "in contact sticking"};
  int start_regime = 0;
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
    const int starts = regime(shot.starts_in_contact, shot.starts_in_stick);
    if (it == 0) start_regime = starts;
    if (starts != start_regime) {
      throw OrbitError("Newton's iterate left the start's regime: no orbit near the guess");
    }
    y = shot.start;  // projected onto the bore in contact
    const int ends = regime(shot.ends_in_contact, shot.ends_in_stick);
    if (ends != start_regime) {
      throw OrbitError(std::string("the shot ends ") + kRegimes[ends] + " where it started " + kRegimes[start_regime] +
                       ": no orbit near the guess");
    }
    const bool in_contact = start_regime > 0, in_stick = start_regime == 2;
    const Vector r = shot.end - y;
    const double residual = r.lpNorm<Eigen::Infinity>();
    const Eigen::MatrixXd basis = in_contact ? flow.tangent_basis(t0, y, in_stick) : Eigen::MatrixXd::Identity(n, n);
    const Eigen::MatrixXd m = basis.transpose() * shot.jacobian * basis;
    // Accepted below the tolerance, after at least one Newton step unless
    // already at the rounding (a settled start meets the tolerance as it is).
    if (residual < s.newton_tolerance && (it > 0 || residual < kPolished)) {
      orbit.starts_in_contact = in_contact;
      orbit.starts_in_stick = in_stick;
      orbit.section_angle_rad = s.section_angle_rad;
      orbit.state = flow.physical(y);
      orbit.keyphasor_states = keyphasor_states(flow, y, t0, s);
      orbit.events = shot.events;
      orbit.monodromy = m;
      orbit.tangent_basis = basis;
      orbit.multipliers = sorted_eigenvalues(m);
      finish_orbit(orbit, shot, it, residual);
      return orbit;
    }
    check_newton("periodic orbit", it, s.max_newton_iterations, residual);
    const Eigen::MatrixXd a = m - Eigen::MatrixXd::Identity(m.rows(), m.cols());
    y += basis * a.fullPivLu().solve(-(basis.transpose() * r));
    if (in_contact) flow.project_to_bore(y);
    if (in_stick) flow.project_to_stick(t0, y);
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
