/// @file
/// The commands a running simulation receives, in simulated time: speed
/// commands, live parameter changes and faults, each stamped. The schedule
/// is the determinism contract of a node: a command stamped ahead applies
/// exactly at its stamp, whatever the pace and however the caller chunks
/// its advance (test_command_schedule, SameStampsSameRunAtAnyChunking); a
/// zero stamp applies at the next instant reached; a stamp already
/// simulated is refused for changes and faults (a change that would rewrite
/// the past is a client's error) and applies at once for a speed command (a
/// controller's late command still steers). Changes and faults are checked
/// on receipt against the scene in force (keys, liveness, ranges; a blade
/// loss's node) and again at their stamp, where the rules between keys and
/// the state decide. A fault becomes its steps at its stamp, from the scene
/// then in force (faults.hpp); a ramp is answered once, at its last step,
/// spanning its steps. ROS-free: the node translates messages into these
/// calls and the answers into feedback.
#pragma once

#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/faults.hpp"
#include "rotor_rub_sim/core/simulation.hpp"

namespace rotor_rub::core {

/// The answer to a parameter change, a fault or one of its ramps: applied
/// from start_s to end_s in `steps` steps, or refused and why.
struct ChangeAnswer {
  std::uint32_t id = 0;  ///< the request's id (a fault's fault_id)
  std::string source;    ///< the request's source; a fault's "fault:<kind>"
  /// The keys and values as applied (a closure clamped at the rotor; an
  /// unbalance added by added_unbalance_node, _me_kg_m, _phase_rad).
  std::map<std::string, std::string> changes;
  /// The keys' values before it (a ramp's before its first step); NaN where
  /// refused, or where a key is no scene key.
  std::map<std::string, double> from;
  bool accepted = false;  ///< applied (steps > 0); false: refused, nothing changed
  double start_s = 0.0;   ///< simulated time applied at (a ramp: its first step), or refused at
  double end_s = 0.0;     ///< a ramp's last step applied; start_s for one step
  std::uint32_t steps = 0;
  /// Refused: why, naming the key, the value and the range. Applied: a note
  /// (a closure stopped at the rotor, a ramp ended early), or "".
  std::string reason;
};

/// The answer to a speed command.
struct SpeedAnswer {
  bool accepted = false;
  double effective_time_s = 0.0;  ///< when it applies (its stamp, or now)
  double accel_rad_per_s2 = 0.0;  ///< the acceleration used (0 asked: the scene's)
  std::string reason;             ///< refused: why, with the value and the range
};

/// Speed commands, parameter changes and faults queued by their stamps and
/// applied to a Simulation at them. Not thread-safe; one per Simulation
/// (clear() when the simulation restarts).
class CommandSchedule {
 public:
  /// output_rate_hz: a ramp's steps, one per output sample (faults.hpp).
  explicit CommandSchedule(double output_rate_hz) : output_rate_hz_(output_rate_hz) {}

  /// A speed command stamped stamp_s (0 or past: now); accel 0 asks for the
  /// scene's acceleration. A repeat of the command in force with nothing
  /// queued changes nothing (the integration is not restarted).
  SpeedAnswer command_speed(Simulation& sim, double stamp_s, double target_rad_per_s, double accel_rad_per_s2);

  /// A parameter change stamped stamp_s (0: now): refused on receipt (the
  /// answer appended), applied now (its answer appended) or queued.
  void change_parameters(Simulation& sim, double stamp_s, const std::map<std::string, std::string>& changes,
                         std::uint32_t id, const std::string& source, std::vector<ChangeAnswer>& answers);

  /// A fault stamped stamp_s (0: now). Throws std::invalid_argument naming
  /// the field, the value and the range when refused on receipt; else
  /// queued, and applied at once when due (its answers appended). Returns
  /// the time its first step applies.
  double inject_fault(Simulation& sim, double stamp_s, const Fault& fault, std::uint32_t id,
                      std::vector<ChangeAnswer>& answers);

  /// The time of the next queued command (infinity when none): where a
  /// caller's advance must stop to apply it.
  double next_time_s() const {
    return pending_.empty() ? std::numeric_limits<double>::infinity() : pending_.front().time_s;
  }
  /// Applies the commands due at sim.time(), appending their answers.
  void apply_due(Simulation& sim, std::vector<ChangeAnswer>& answers);
  /// Answers the ramps begun and not ended (the run ended or failed, a
  /// reset, a stop): the steps made, and why the rest were not; their later
  /// steps are dropped.
  void close_open_ramps(const Simulation& sim, const std::string& why, std::vector<ChangeAnswer>& answers);
  /// Forgets everything queued (a restart).
  void clear();
  bool empty() const { return pending_.empty(); }  ///< nothing queued

  /// "" when stamp_s may be queued now, else why not (a stamp already
  /// simulated; 0 means the next instant reached).
  static std::string past_stamp(double stamp_s, double now_s);
  /// The source a fault's answers carry: "fault:<kind>".
  static std::string fault_source(FaultKind kind) { return std::string("fault:") + to_string(kind); }

 private:
  struct Pending {
    enum class Kind : std::uint8_t { kSpeed, kParameters, kFault };
    double time_s = 0.0;
    Kind kind = Kind::kSpeed;
    double target_rad_per_s = 0.0, accel_rad_per_s2 = 0.0;
    std::map<std::string, std::string> changes;
    Fault fault;
    std::uint32_t id = 0;
    std::string source;
    bool stop_at_rotor = false;                    // a clearance closure (FaultStep)
    std::vector<RotorUnbalance> unbalances_added;  // a flexible rotor's blade loss (FaultStep)
    std::uint64_t ramp = 0;                        // a ramp's steps share it (ramps_); 0: not a ramp
    bool ramp_last = false;                        // the ramp's last step: its answer is due
  };
  struct OpenRamp {
    std::uint32_t id = 0;
    std::string source;
    double start_s = 0.0;
    std::uint32_t applied = 0;
    std::map<std::string, double> from;
    std::map<std::string, std::string> reached;
    std::string note;
  };
  struct Outcome {
    bool accepted = false;
    std::string reason;
    std::map<std::string, std::string> echoed;
  };

  // Queues p after every command of its time or earlier.
  void enqueue(Pending p);
  // Applies a change now (checked again: the state may forbid it).
  Outcome try_change(Simulation& sim, std::map<std::string, std::string> changes, bool stop_at_rotor,
                     const std::vector<RotorUnbalance>& unbalances_added) const;
  void apply_change(Simulation& sim, const Pending& p, std::vector<ChangeAnswer>& answers);
  void apply_ramp_step(Simulation& sim, const Pending& p, std::vector<ChangeAnswer>& answers);
  void expand_fault(Simulation& sim, const Pending& p, std::vector<ChangeAnswer>& answers);

  double output_rate_hz_;
  std::deque<Pending> pending_;  // sorted by time, stable in arrival order (taken from the front)
  std::map<std::uint64_t, OpenRamp> ramps_;
  std::uint64_t next_ramp_ = 1;
  // The speed command in force (a repeat of it changes nothing); NaN until
  // the first, when the scene's run-up is in force.
  double applied_target_ = std::numeric_limits<double>::quiet_NaN();
  double applied_accel_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace rotor_rub::core
