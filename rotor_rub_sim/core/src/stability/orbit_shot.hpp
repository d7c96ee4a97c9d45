// One shot of the Jeffcott's event-driven flow with its variational
// equations (orbit_shot.cpp): what the shooting (periodic_orbit.cpp,
// turning_orbit.cpp) and the orbits' continuation (orbit_continuation.cpp)
// build on.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <vector>

#include "rotor_rub_sim/core/periodic_orbit.hpp"
#include "rub_flow.hpp"

namespace rotor_rub::core {

struct OrbitShot {
  Eigen::VectorXd start;     // y(t0): projected onto the bore when it starts in contact
  Eigen::VectorXd end;       // y(t1)
  Eigen::MatrixXd jacobian;  // d y(t1) / d y(t0) (empty without)
  std::vector<OrbitEvent> events;
  bool starts_in_contact = false, ends_in_contact = false;  // sliding or sticking
  bool starts_in_stick = false, ends_in_stick = false;
  double slowest_impact = 0.0, closest_miss = 0.0;  // OrbitFlow's
};

// The flow from y0 (RubFlow's units) at t0 to t1: in contact when y0 lies
// within 1e-8 C of the bore and is pressed onto it, sticking when its slip
// is below kStickSlip and the cone holds it. Throws OrbitError.
OrbitShot shoot(const RubFlow& flow, const Eigen::VectorXd& y0, double t0_s, double t1_s, const OrbitSettings& s,
                bool with_jacobian);

// The states at the keyphasor over an orbit from y at its section t0
// (PeriodicOrbit::keyphasor_states).
std::vector<Eigen::VectorXd> keyphasor_states(const RubFlow& flow, const Eigen::VectorXd& y, double t0_s,
                                              const OrbitSettings& s);

// The eigenvalues of m, the largest modulus first.
std::vector<std::complex<double>> sorted_eigenvalues(const Eigen::MatrixXd& m);

// std::invalid_argument for a scene, speed or settings the orbits do not
// model (a motor drive, a speed not above 0, periods below 1).
void check_scene(const ModelParameters& p, double w_rad_per_s, const OrbitSettings& s);
// OrbitError for an orbit that passes closer to the bore than kGrazingGap.
void check_grazing(double closest_miss);

// The end of find_periodic_orbit's and find_turning_orbit's Newton loops:
// the iterations, the residual and the shot's closest approaches into the
// orbit (OrbitError for a grazing one, check_grazing).
template <class Orbit>
void finish_orbit(Orbit& orbit, const OrbitShot& shot, int iterations, double residual) {
  orbit.newton_iterations = iterations;
  orbit.residual = residual;
  orbit.slowest_impact = shot.slowest_impact;
  orbit.closest_miss = shot.closest_miss;
  check_grazing(orbit.closest_miss);
}
// OrbitError "no WHAT near the guess" once Newton has taken its
// max_iterations or its residual is no longer finite.
void check_newton(const char* what, int iterations, int max_iterations, double residual);

// A shooting residual this small (of C and C w) needs no Newton step: a
// settled start meets the tolerance as it is (find_periodic_orbit,
// find_turning_orbit).
inline constexpr double kPolished = 1e-13;

// RubFlow's settle apex for the settings (the integrator's tolerance of C).
inline double settle_apex_m(const ModelParameters& p, const OrbitSettings& s) { return s.tolerance * p.clearance_m; }

}  // namespace rotor_rub::core
