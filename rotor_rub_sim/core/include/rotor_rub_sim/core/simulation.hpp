/// @file
/// The simulation loop: drives a contact method through time, restarts it at
/// every drive discontinuity, and delivers samples on the output grid
/// (t_k = k / output_rate_hz exactly, from dense output) and contact events, in
/// time order, to an observer. Time is an argument, never read from a clock
/// (the wall clock only measures cost).
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/contact_method.hpp"
#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/invariants.hpp"
#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"

namespace rotor_rub::core {

/// What a Simulation delivers to, in time order: override the calls wanted
/// (every one defaults to nothing). Called from advance_to(), on its thread.
class SimulationObserver {
 public:
  virtual ~SimulationObserver() = default;
  /// A sample on the output grid t_k = k / output_rate_hz (k >= 0), the state
  /// from the method's dense output; each passed the invariants' check.
  virtual void on_sample(const Sample& /*s*/) {}
  /// A contact event (touchdown, lift-off, graze) at its located time, before
  /// the samples after it.
  virtual void on_event(const ContactEvent& /*e*/) {}
  /// A keyphasor: once per revolution, when the spin angle phi passes a
  /// multiple of 2 pi (the unbalance pointing along +x), the state at that
  /// instant from the method's dense output (not the nearest sample). Called
  /// only when wants_keyphasor(); in time order with the samples. The mark at
  /// the start angle itself (t = 0) is not one.
  virtual bool wants_keyphasor() const { return false; }
  /// A keyphasor mark's state (see wants_keyphasor()).
  virtual void on_keyphasor(const Sample& /*s*/) {}
  /// The proximity probes' samples: the state at k / scene.probes.rate_hz
  /// (k >= 1) from the dense output, called only when wants_probes() and the
  /// rate is > 0; in time order with the samples (probes.hpp reads them).
  virtual bool wants_probes() const { return false; }
  /// A probe sample's state (see wants_probes()).
  virtual void on_probe_sample(const Sample& /*s*/) {}
  /// A flexible rotor's deflected shaft (every node's lateral displacement)
  /// at k / shaft_rate_hz() (k >= 1) from the dense output, called only for a
  /// scene with a rotor_file and a rate > 0; in time order with the samples.
  virtual double shaft_rate_hz() const { return 0.0; }
  /// The shaft's nodes at one instant (see shaft_rate_hz()).
  virtual void on_shaft_sample(const ShaftSample& /*s*/) {}
};

/// How a run failed: the class (run_types.hpp), the simulated time and a
/// message naming what went wrong.
struct RunFailure {
  FailureClass failure_class;  ///< what kind of failure (its name: to_string)
  double time_s;               ///< where the failing step began or the invariant broke [s]
  std::string message;         ///< what went wrong, with the value and its limit
};

/// A scene's run, advanced by the caller: the loop around one ContactMethod
/// (made from the scene's method and integrator), with the speed profile, the
/// commands and live changes, the invariants' checks and the output grid.
/// Not thread-safe; one per run.
class Simulation {
 public:
  /// Checks the scene (validate_scene: throws SceneError naming the key, the
  /// value and the accepted range) and starts at rest at t = 0.
  explicit Simulation(const Scene& scene);

  /// Advances to min(t_s, end_time_s), delivering samples with t <= t_s.
  /// Returns false once the method has failed (see failure()); samples and
  /// events up to the end of the last completed step have been delivered (the
  /// failing step's are withheld: its state is not trusted).
  bool advance_to(double t_s, SimulationObserver& observer);

  /// A speed command taking effect at the current time(): a ramp at
  /// accel_magnitude to target_rad_per_s, then held. Throws
  /// std::invalid_argument (naming the value and range) when out of range.
  void command_speed(double target_rad_per_s, double accel_magnitude_rad_per_s2);

  /// Live parameter changes taking effect at the current time(): a map of
  /// scene keys (those scene_keys() marks live) to values as text. The state
  /// (positions, velocities, spin) is continuous across the change; the
  /// contact regime is decided again (ContactMethod::change_model), and a
  /// contact that ends there is a lift-off event at time(). All keys apply
  /// at once, or none: throws SceneError naming the key, the value and the
  /// reason, the simulation unchanged, when a key is unknown, not live (its
  /// live_refusal), has no effect on this scene, or its value is out of
  /// range, breaks a rule between keys, or would put the stator into the
  /// rotor (a clearance below the present rotor-stator distance), or the
  /// run has failed. A restart that fails (MethodFailure, as a step may) ends
  /// the run there: failure() says so. unbalances_added: unbalances added to
  /// a flexible rotor's at their nodes (a blade loss, FaultStep), in the
  /// file's angles; a Jeffcott's unbalance is its keys (SceneError).
  void change_parameters(const std::map<std::string, std::string>& changes,
                         const std::vector<RotorUnbalance>& unbalances_added = {});

  /// Moves the end (e.g. to infinity, for a node that keeps running at the
  /// last speed after the scene's end_time_s). Must not be before time().
  /// Past the scene's end the wall budget (max_wall_time_s) no longer applies.
  void set_end_time(double t_s);

  double time() const { return time_s_; }  ///< simulated time delivered so far
  /// |r_r - r_s| at time() [m] (a clearance closure stops there).
  double rotor_stator_distance_m() const;
  /// The scene as run: integrator `auto` resolved to the registry's choice.
  const Scene& scene() const { return scene_; }
  /// The speed profile with the commands so far.
  const SpeedProfile& profile() const { return profile_; }
  /// A flexible rotor's node positions along the shaft [m] (node order; the
  /// nodes of ShaftSample); empty for the Jeffcott.
  std::vector<double> shaft_node_z_m() const;
  /// A flexible rotor's rub station node, or -1 (the Jeffcott).
  int shaft_station_node() const;
  /// What the contact meets (test_run_summary).
  struct ContactPoint {
    /// The rotor's mass at the contact point [kg]: the Jeffcott's
    /// rotor_mass_kg, a flexible rotor's station mass m_st.
    double mass_kg = 0.0;
    /// The rotor against the stator [kg]: 1 / (1/m_r + 1/m_s); m_r alone on
    /// a rigid stator.
    double effective_mass_kg = 0.0;
    /// The penalty spring k_c on that mass, sqrt(k_c / m_eff) [rad/s]: the
    /// contact mode, whose period a penalty run resolves.
    double contact_mode_rad_per_s = 0.0;
    /// The penalty damper c_c on that mode [N s/m]: contact_damping_N_s_per_m
    /// where the scene gives it, else the restitution's (contact_law.hpp).
    double contact_damping_N_s_per_m = 0.0;
  };
  /// The contact point of the scene as run.
  ContactPoint contact_point() const;
  /// A flexible rotor's reduction as run: its planar modes (0 for the
  /// Jeffcott) and its truncation error as judged at the start.
  struct Reduction {
    long planar_modes = 0;        ///< the count run (auto's choice where asked); 0: the Jeffcott
    TruncationReport truncation;  ///< the unbalance response's error, judged at the start
  };
  /// The scene's (see Reduction).
  Reduction reduction() const;
  /// The run's cost so far (steps, evaluations, events; wall_time_s is the
  /// integration's own time).
  const RunStats& stats() const { return method_->stats(); }
  /// Set once a step has failed; the run stays there.
  const std::optional<RunFailure>& failure() const { return failure_; }

 private:
  void deliver_until(double t_s, SimulationObserver& observer);
  void deliver_marks_before(double t_s, bool inclusive, SimulationObserver& observer);
  void deliver_probes_before(double t_s, bool inclusive, SimulationObserver& observer);
  void deliver_shaft_before(double t_s, bool inclusive, SimulationObserver& observer);
  /// The first time in [time(), t_s] at which a motor's spin angle reaches
  /// angle_rad, on the dense output; infinity if it does not get there.
  double spin_angle_time(double angle_rad, double t_s) const;
  void count_and_deliver(const ContactEvent& e, SimulationObserver& observer);

  Scene scene_;
  SpeedProfile profile_;
  std::unique_ptr<ContactMethod> method_;
  InvariantLimits limits_;
  double wall_budget_s_;  ///< max_wall_time_s, or infinity once the end is moved past the scene's
  double time_s_ = 0.0;
  long next_sample_ = 0;
  double next_mark_angle_rad_ = 0.0;                ///< the next keyphasor angle (a multiple of 2 pi)
  long next_probe_sample_ = 1;                      ///< the probes' next sample index (k / probe rate)
  long next_shaft_sample_ = 1;                      ///< the shaft's next sample index (k / its rate)
  ShaftSample shaft_;                               ///< reused: no allocation per shaft sample
  static constexpr long kPassesPerClockRead = 256;  // the wall budget's clock reads (advance_to)
  long passes_since_clock_ = 0;
  double t_limit_s_ = 0.0;                 ///< the drive discontinuity the last step was bounded by
  bool break_due_ = false;                 ///< the last step ended on it
  std::vector<ContactEvent> step_events_;  ///< found, not yet delivered
  std::optional<RunFailure> failure_;
};

/// Throws std::invalid_argument (naming the value and the accepted range) when
/// a speed command is out of range for the scene: the check command_speed
/// makes, for callers that queue a command for later.
void check_speed_command(const Scene& scene, double target_rad_per_s, double accel_magnitude_rad_per_s2);

/// The running scene with live changes applied and checked, as
/// Simulation::change_parameters checks them before it looks at the state:
/// throws SceneError (an unknown or non-live key, one inert on this scene, a
/// value out of range, and with rules_between_keys a rule between keys
/// broken). A caller that queues a change for later (the node, on receipt of
/// a stamped change) checks without the rules between keys: they depend on
/// the changes applied before the stamp, so only the stamp can judge them.
Scene with_live_changes(const Scene& running, const std::map<std::string, std::string>& changes,
                        bool rules_between_keys);
/// The running scene with unbalances added to its flexible rotor (the
/// loaded model's forcing, FlexibleRotorModel::with_unbalances; the file is
/// not read again). Throws SceneError for the Jeffcott (its unbalance is
/// eccentricity_m and unbalance_phase_rad) and for a node out of range.
Scene with_unbalances_added(const Scene& running, const std::vector<RotorUnbalance>& added);

/// A whole run's outcome (run_scene).
struct RunResult {
  RunStats stats;                     ///< the run's cost (steps, evaluations, wall time)
  std::vector<ContactEvent> events;   ///< every event, in time order
  std::optional<RunFailure> failure;  ///< empty for a run that reached end_time_s
};
/// Runs the whole scene from 0 to end_time_s, delivering to observer, and
/// returns its cost, events and failure, if any. Throws SceneError for a
/// scene that does not validate.
RunResult run_scene(const Scene& scene, SimulationObserver& observer);

}  // namespace rotor_rub::core
