/// @file
/// What a run reports: samples, contact events, cost, failures.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/model.hpp"

namespace rotor_rub::core {

/// Time resolution of located events [s] (event_location.hpp): far below any
/// step of interest; neighbouring times lie closer than this up to t = 512 s.
inline constexpr double kEventTimeTolerance_s = 1e-13;

/// The resolution a located event reaches at t_s [s]: kEventTimeTolerance_s,
/// or, from t = 512 s on, where neighbouring doubles lie farther apart, the
/// step to the next one. A located event lies on the far side of its root by
/// up to this much.
inline double event_time_resolution_s(double t_s) {
  const double t = std::abs(t_s);
  return std::max(kEventTimeTolerance_s, std::nextafter(t, std::numeric_limits<double>::infinity()) - t);
}

/// The physical state at one instant, whatever the method's internal state.
struct Sample {
  double t_s = 0.0;                              ///< the sample's time [s]
  Kinematics kin;                                ///< rotor and stator positions and velocities, in the casing's frame
  DriveState drive;                              ///< the spin: angle, speed, acceleration, motor torque
  double normal_force_N = 0.0;                   ///< F_n >= 0 on the rotor, along -n
  double friction_force_N = 0.0;                 ///< signed along the tangent t, on the rotor
  Vec2 contact_force_on_rotor_N = Vec2::Zero();  ///< -F_n n + F_t t, in x and y
  double penetration_m = 0.0;                    ///< delta - C: < 0 is the gap
  double sliding_velocity_m_per_s = 0.0;         ///< the contact point's relative speed along t
  bool in_contact = false;                       ///< the rotor on the bore (or pressed into it: penalty)
  /// In contact and sticking (rolling, v_slide held at 0): the rigid methods'
  /// stick regime; the penalty method's creep band |c_t v_slide| < f F_n.
  bool sticking = false;
  /// The drive's torque on the rotor (the motor's, or what an ideal
  /// prescribed drive applies) and the rub's, R_r F_t [N m] (model.hpp).
  double drive_torque_N_m = 0.0;
  double friction_torque_N_m = 0.0;  ///< the rub's torque on the spin, R_r F_t
  /// What the proximity probes read, in the casing's frame [m]: the rotor's
  /// centre, or a flexible rotor's displacement at its probe node
  /// (RotorSettings::probe_node), which need not be the rub station.
  Vec2 probe_displacement_m = Vec2::Zero();
};

/// A flexible rotor's deflected shaft at t_s: each node's lateral
/// displacement [m] in the casing's frame, in node order (the rub station's
/// is the state's rotor position; Simulation::shaft_node_z_m says where the
/// nodes sit along the shaft).
struct ShaftSample {
  double t_s = 0.0;                       ///< the instant [s]
  std::vector<Vec2> node_displacement_m;  ///< per node, in node order
};

/// What a contact event is.
enum class EventKind {
  kTouchdown,  ///< sustained contact begins
  kLiftoff,    ///< sustained contact ends
  kGraze,      ///< a touch or bounce with no sustained contact
};
/// Every EventKind, for parsing a name back (to_string's inverse).
inline constexpr std::array<EventKind, 3> kAllEventKinds{EventKind::kTouchdown, EventKind::kLiftoff, EventKind::kGraze};
/// The event kind's name in the node's messages, the runner's JSON and the
/// tools' tables: touchdown, liftoff, graze. No default label: -Werror=switch
/// names a kind added without a name.
inline const char* to_string(EventKind k) {
  switch (k) {
    case EventKind::kTouchdown:
      return "touchdown";
    case EventKind::kLiftoff:
      return "liftoff";
    case EventKind::kGraze:
      return "graze";
  }
  throw std::logic_error("to_string: not an EventKind");
}

/// A located contact event (ContactMethod::step, SimulationObserver::on_event).
struct ContactEvent {
  double t_s = 0.0;                        ///< the located time [s]
  EventKind kind = EventKind::kTouchdown;  ///< touchdown, lift-off or graze
  double normal_velocity_m_per_s = 0.0;    ///< closing speed at touchdown/graze
  double impulse_N_s = 0.0;                ///< impact impulse (rigid methods)
};

/// The cost of a run. wall_time_s is the integration's own time.
struct RunStats {
  long steps = 0;                 ///< accepted steps
  long rejected_steps = 0;        ///< rejected by error control or by a method rule
  long rhs_evals = 0;             ///< right-hand-side (derivative) evaluations
  long jacobian_evals = 0;        ///< stiff integrator only
  long root_iterations = 0;       ///< root-finder function evaluations (events, forces)
  long touchdowns = 0;            ///< touchdown events located
  long liftoffs = 0;              ///< lift-off events located
  long grazes = 0;                ///< graze events located
  long restarts = 0;              ///< integrator restarts (events, profile breaks, projections)
  long friction_transitions = 0;  ///< rigid methods: slip -> stick, stick -> slip, slip reversals
  long integrator_switches = 0;   ///< dop853_rosenbrock4 only: dop853 <-> RODASP by the stiffness test
  double wall_time_s = 0.0;       ///< spent in advance_to [s] (the construction excluded)
  double rhs_time_s = 0.0;        ///< profile_cost only: in derivative evaluation, iteration included
  double iteration_time_s = 0.0;  ///< profile_cost only: in the normal force iteration
  double event_time_s = 0.0;      ///< profile_cost only: event scan, location and handling (impact law), no RHS
  double restart_time_s = 0.0;    ///< profile_cost only: entering the next regime, restarts (their RHS in rhs too)
  double output_time_s = 0.0;     ///< profile_cost only: samples, keyphasor and probes delivered, with their checks
  double max_constraint_violation_m = 0.0;          ///< rigid methods: max |delta - C| in contact at step ends
  double min_abs_sliding_velocity_m_per_s = 1e300;  ///< over contact, at step ends
};

/// How a run fails. stalled: the step budget, the minimum step or the chatter
/// counter; diverged: a non-finite or blown-up state; not_converged: the normal
/// force root finder; timed_out: the wall-time budget (max_wall_time_s);
/// invariant_violated: an accepted step broke what the contact law guarantees
/// (non-penetration of a rigid method, the friction cone, dissipative friction,
/// finiteness; see invariants.hpp): a defect made loud, never an `ok` run.
enum class FailureClass { kStalled, kDiverged, kNotConverged, kTimedOut, kInvariantViolated };
/// The class's name in the outputs: stalled, diverged, not_converged,
/// timed_out, invariant_violated.
inline const char* to_string(FailureClass c) {
  switch (c) {
    case FailureClass::kStalled:
      return "stalled";
    case FailureClass::kDiverged:
      return "diverged";
    case FailureClass::kNotConverged:
      return "not_converged";
    case FailureClass::kTimedOut:
      return "timed_out";
    case FailureClass::kInvariantViolated:
      return "invariant_violated";
  }
  throw std::logic_error("to_string: not a FailureClass");
}

/// The process exit status of a run that failed, shared by the runner and the
/// node: 3 stalled, 4 diverged, 5 not converged, 7 timed out (6 is the
/// runner's output error), 8 invariant violated.
inline int exit_status(FailureClass c) {
  switch (c) {
    case FailureClass::kStalled:
      return 3;
    case FailureClass::kDiverged:
      return 4;
    case FailureClass::kNotConverged:
      return 5;
    case FailureClass::kTimedOut:
      return 7;
    case FailureClass::kInvariantViolated:
      return 8;
  }
  return 1;
}

/// A failed run: thrown by the methods, caught by the simulation loop.
class MethodFailure : public std::runtime_error {
 public:
  /// A failure of class c at t_s, what naming the cause.
  MethodFailure(FailureClass c, double t_s, const std::string& what)
      : std::runtime_error(what), failure_class(c), time_s(t_s) {}
  FailureClass failure_class;  ///< what kind of failure
  double time_s;               ///< where it happened [s]
};

/// Shared guard of the adaptive integrators: a run that spends its step
/// budget or whose step collapses is stalled, reported rather than hung.
inline void check_step_budget(const RunStats& stats, long max_steps, double dt_s, double min_step_s, double t_s) {
  if (stats.steps + stats.rejected_steps >= max_steps) {
    throw MethodFailure(FailureClass::kStalled, t_s, "step budget of " + std::to_string(max_steps) + " steps spent");
  }
  if (!(std::abs(dt_s) >= min_step_s)) {
    char what[160];
    std::snprintf(what, sizeof what, "step size %.3g s fell below min_step_s = %.3g s", dt_s, min_step_s);
    throw MethodFailure(FailureClass::kStalled, t_s, what);
  }
}

}  // namespace rotor_rub::core
