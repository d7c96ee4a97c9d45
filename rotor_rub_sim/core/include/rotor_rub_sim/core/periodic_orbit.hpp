/// @file
/// Periodic orbits of the Jeffcott rotor's rub under the prescribed drive at
/// a constant speed w, and their Floquet multipliers: shooting on the
/// event-driven flow of the rigid contact (the switching method's physics:
/// free flight, impacts by contact_law.hpp's law, the rotor held on the bore
/// sliding with the friction f N against the slip or sticking (rolling,
/// v_slide = 0 held by the stick force while it lies in the cone f N),
/// lift-off where N falls to 0), with the monodromy matrix built exactly
/// from the variational equations of each phase and the saltation matrix of
/// each event:
///   S = G_x + (f+ - G_x f-) h_x / (h_x f-)
/// (h the event's function, G the jump it applies, f-/f+ the fields before
/// and after). A lift-off's and a breakaway's (the stick force reaching the
/// cone) are the identity (the two fields agree there); a plastic impact's
/// has rank n - 1 (the normal velocity dies: a multiplier 0), and n - 2 when
/// a contact follows it (the gap dies too); a slip's stop (h = v_slide, no
/// jump) switches the friction, and into a stick it has rank n - 1 (the
/// slip dies: Filippov's sliding mode). The forcing is periodic in
/// T = 2 pi / w, so an orbit of n periods is a fixed point of the flow over
/// n T from a spin angle psi (the section, 0 unless chosen): Newton on the
/// state there, on the bore's tangent space when the orbit starts in
/// contact, and on the stick's when it starts sticking.
///
/// The state is the free layout's (state_layout.hpp): the rotor's position
/// and, with an elastic stator, the stator's, then their velocities [m,
/// m/s], in the casing's frame. Each phase is integrated with its
/// variational equations by Runge-Kutta-Fehlberg 7(8) in units of the
/// clearance C and of C w; the contact field's Jacobian is a central
/// difference (the free flight is affine in the state: its Jacobian is a
/// difference of unit steps, exact to rounding).
///
/// Limits, each reported by OrbitError: the Jeffcott rotor only, the
/// prescribed drive, the rigid contact (not the penalty's spring); an orbit
/// that grazes the bore (an impact slower than kGrazingVelocity of C w, or a
/// free-flight apex within kGrazingGap of C of the bore) has no monodromy
/// there, nor one whose slip comes to rest slower than kGrazingVelocity of
/// C w^2 or at the cone's edge (the stick force within kConeEdge of f N:
/// a neighbour would stick where it slips on); more than
/// OrbitSettings::max_events events in a forcing period (a chattering
/// sequence of impacts) end the shot. Tests: test_periodic_orbit.cpp.
#pragma once

#include <Eigen/Core>
#include <complex>
#include <stdexcept>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

/// An orbit this module cannot find or linearise: why, in a sentence.
class OrbitError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An impact slower than this fraction of C w grazes the bore: the saltation
/// matrix divides by it.
inline constexpr double kGrazingVelocity = 1e-6;
/// A free flight's closest approach within this fraction of C short of the
/// bore grazes it: a neighbouring orbit's impact would be missed.
inline constexpr double kGrazingGap = 1e-9;
/// A slip that stops with a stick force within this fraction of the cone
/// f N of its edge: whether a neighbour sticks or slips on parts by a
/// rounding of the Newton step, and the flow has no derivative there.
inline constexpr double kConeEdge = 1e-6;

struct OrbitSettings {
  int periods = 1;                 ///< the forcing periods T of the orbit (period-n)
  double tolerance = 1e-11;        ///< the integrator's, relative and in units of C and C w
  double newton_tolerance = 1e-9;  ///< |x(nT) - x(0)| accepted, in units of C and C w
  int max_newton_iterations = 30;  ///< then OrbitError
  int max_events = 200;            ///< per forcing period, then OrbitError (chattering)
  int min_steps_per_period = 64;   ///< the integrator's longest step T / this
  /// The section: the spin angle psi in [0, 2 pi) where an orbit's state is
  /// taken (t = psi / w); a guess is a state there.
  double section_angle_rad = 0.0;
};

/// An event of the flow. kImpact: an impact after which the flight goes on
/// (a rebound, or a plastic impact not pressed onto the bore); kTouchdown: a
/// plastic impact that starts a contact; kLiftOff: the normal force falls
/// to 0; kStick: the slip stops and the contact sticks; kReversal: the slip
/// stops and goes on the other way; kSlip: a stick's force reaches the
/// cone and the contact slides.
struct OrbitEvent {
  enum class Kind { kImpact, kTouchdown, kLiftOff, kStick, kReversal, kSlip };
  Kind kind = Kind::kImpact;
  double time_s = 0.0;
  double normal_velocity_m_per_s = 0.0;  ///< the closing velocity of an impact
};
const char* to_string(OrbitEvent::Kind kind);
/// An impact or a touchdown (its normal_velocity_m_per_s is the closing one).
inline bool is_impact(OrbitEvent::Kind kind) {
  return kind == OrbitEvent::Kind::kImpact || kind == OrbitEvent::Kind::kTouchdown;
}
/// The event starts a free flight (an impact that rebounds, a lift-off).
inline bool starts_flight(OrbitEvent::Kind kind) {
  return kind == OrbitEvent::Kind::kImpact || kind == OrbitEvent::Kind::kLiftOff;
}

/// The flow from t0 to t1 with its Jacobian.
struct OrbitFlow {
  Eigen::VectorXd state;  ///< x(t1)
  /// d x(t1) / d x(t0); from a start on the bore (or sticking) along its
  /// tangent space only (the start's projection onto it is not in it:
  /// ThroughStickPhasesTheMonodromyIsTheFlowsDerivative)
  Eigen::MatrixXd jacobian;
  std::vector<OrbitEvent> events;
  bool ends_in_contact = false;
  /// The slowest impact's closing velocity over C w and the free flights'
  /// closest approach short of the bore over C (+infinity without either).
  double slowest_impact = 0.0, closest_miss = 0.0;
};

/// A periodic orbit and its stability.
struct PeriodicOrbit {
  double speed_rad_per_s = 0.0;
  /// The continuation parameter's value here (orbit_continuation.hpp: the
  /// speed, or a scene key's value); find_periodic_orbit leaves the speed.
  double parameter = 0.0;
  double period_s = 0.0;  ///< n T
  int periods = 1;
  double section_angle_rad = 0.0;  ///< OrbitSettings'
  Eigen::VectorXd state;           ///< x at the section (t = psi / w)
  /// x at the keyphasor (spin angle 0 mod 2 pi) once per forcing period over
  /// the orbit, the first at or after the section: what a run's Poincare
  /// points (rotor_rub_bifurcation) see of it, n of them.
  std::vector<Eigen::VectorXd> keyphasor_states;
  bool starts_in_contact = false;
  bool starts_in_stick = false;  ///< in contact, sticking
  /// Periodic in the frame turning with the shaft (turning_orbit.hpp):
  /// period_s its own, the monodromy's trivial multiplier (1: the flow's
  /// direction) apart from the multipliers.
  bool turning = false;
  double trivial_multiplier = 0.0;
  std::vector<OrbitEvent> events;  ///< over one orbit, t in (psi / w, psi / w + n T]
  /// d y(nT) / d y(0) of y = (positions / C, velocities / (C w)); starting
  /// in contact, its part on the bore's tangent space in y (n - 2 columns of
  /// an orthonormal basis of it, tangent_basis; sticking, the stick's, n - 3).
  Eigen::MatrixXd monodromy;
  Eigen::MatrixXd tangent_basis;
  /// The monodromy's eigenvalues, the largest modulus first.
  std::vector<std::complex<double>> multipliers;
  int newton_iterations = 0;
  double residual = 0.0;                            ///< |x(nT) - x(0)| in units of C and C w
  double slowest_impact = 0.0, closest_miss = 0.0;  ///< OrbitFlow's
  /// Every multiplier inside the unit circle.
  bool stable() const { return !multipliers.empty() && std::abs(multipliers.front()) < 1.0; }
};

/// The flow of the Jeffcott scene p at the constant speed w from x0 at t0
/// (its spin angle w t0) to t1, in free flight, or in contact when x0 is on
/// the bore and pressed onto it. Throws OrbitError (above) and
/// std::invalid_argument for a scene outside the limits.
OrbitFlow orbit_flow(const ModelParameters& p, double w_rad_per_s, const Eigen::VectorXd& x0, double t0_s, double t1_s,
                     const OrbitSettings& settings = {});

/// The periodic orbit of n = settings.periods forcing periods near guess (a
/// state at the section's spin angle), found by Newton on the shooting
/// residual.
/// Throws OrbitError when Newton does not converge (no orbit near the
/// guess), the orbit grazes (the bore or the cone's edge) or chatters.
PeriodicOrbit find_periodic_orbit(const ModelParameters& p, double w_rad_per_s, const Eigen::VectorXd& guess,
                                  const OrbitSettings& settings = {});

/// The state at the section's spin angle after `periods` forcing periods of
/// the flow from the rotor and stator at rest on their springs' centres: a
/// guess for a stable orbit.
Eigen::VectorXd settled_state(const ModelParameters& p, double w_rad_per_s, int periods,
                              const OrbitSettings& settings = {});

}  // namespace rotor_rub::core
