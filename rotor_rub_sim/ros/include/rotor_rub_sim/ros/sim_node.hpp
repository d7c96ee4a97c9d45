// The ROS node: a thin shell around core::Simulation. It owns the pacing
// (real_time_factor), turns samples and events into messages, and turns
// speed commands and service calls into core calls. Everything runs on one
// thread (callbacks are served between simulation chunks), so the order of
// core calls, and hence the trajectory, depends only on simulated times.
//
// Speed command timing (the determinism contract): a command stamped with a
// simulated time not yet reached is applied exactly at that time; one with a
// zero or past stamp is applied at the simulated time the node has reached
// when it serves the callback (a chunk boundary, on the output grid). The
// same stamped command sequence therefore gives the same trajectory at any
// real-time factor. Parameter changes and faults share the queue (at one
// stamp, in arrival order): a future stamp applies exactly then, a zero stamp
// at the time reached, and a stamp already simulated is refused.
//
// Its definitions by job: sim_node.cpp (construction, the run loop, pacing
// and lockstep), sim_node_output.cpp (topics, tf, /clock; publishing with
// recording is NodeOutput's, node_output.hpp),
// sim_node_commands.cpp (commands, changes, faults, services),
// sim_node_diagnostics.cpp (its tasks; recording them is
// RecordedDiagnostics', recorded_diagnostics.hpp); their shared helper in
// src/sim_node_io.hpp.
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/update_functions.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "rotor_rub_msgs/ContactEvent.h"
#include "rotor_rub_msgs/Fault.h"
#include "rotor_rub_msgs/InjectFault.h"
#include "rotor_rub_msgs/Keyphasor.h"
#include "rotor_rub_msgs/ParameterChange.h"
#include "rotor_rub_msgs/ProbeSignals.h"
#include "rotor_rub_msgs/RotorState.h"
#include "rotor_rub_msgs/ShaftDeflection.h"
#include "rotor_rub_msgs/SolverStats.h"
#include "rotor_rub_msgs/SpeedCommand.h"
#include "rotor_rub_msgs/StepSimulation.h"
#include "rotor_rub_sim/core/command_schedule.hpp"
#include "rotor_rub_sim/core/faults.hpp"
#include "rotor_rub_sim/core/probes.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "rotor_rub_sim/ros/markers.hpp"
#include "rotor_rub_sim/ros/node_config.hpp"
#include "rotor_rub_sim/ros/node_output.hpp"
#include "rotor_rub_sim/ros/pacing.hpp"
#include "rotor_rub_sim/ros/reconfigure_server.hpp"
#include "rotor_rub_sim/ros/recorded_diagnostics.hpp"

namespace rotor_rub::ros_node {

class SimNode : public core::SimulationObserver {
 public:
  // Throws std::runtime_error when the record_bag cannot be opened.
  SimNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const NodeSetup& setup);
  // Runs until shutdown or, with end_action exit, the end of the scene.
  // Returns the process exit status: 0 ok, 1 start-up failure, or the
  // method's failure as rotor_rub_run gives it (core::exit_status): 3
  // stalled, 4 diverged, 5 not converged, 7 timed out, 8 invariant violated.
  int run();

  void on_sample(const core::Sample& s) override;
  void on_event(const core::ContactEvent& e) override;
  // The keyphasor and the probes (topics "keyphasor" and "probes").
  bool wants_keyphasor() const override { return true; }
  void on_keyphasor(const core::Sample& s) override;
  bool wants_probes() const override { return probe_pair_.has_value(); }
  void on_probe_sample(const core::Sample& s) override;
  // A flexible rotor's deflected shaft (topic "shaft" and its markers).
  double shaft_rate_hz() const override { return shaft_pub_ ? config_.shaft_rate_hz : 0.0; }
  void on_shaft_sample(const core::ShaftSample& s) override;

 private:
  enum class Status : uint8_t { kRunning, kPaused, kFinished, kFailed };
  bool wait_for_subscribers();
  void restart_simulation();
  // Advances to t_s, applying queued commands at their times on the way.
  void advance_to(double t_s);
  // Applies the queued commands due now and answers them.
  void apply_due_commands();
  // Publishes and logs each answer (parameter_change_feedback); an applied
  // change updates what shows the scene (reconfigure's values, the bore).
  void answer(const std::vector<core::ChangeAnswer>& answers);
  // A refusal on receipt, before the schedule sees it (a malformed message).
  void refuse_change(const std::map<std::string, std::string>& changes, uint32_t id, const std::string& source,
                     const std::string& reason);
  // Answers the ramps begun and not ended (core::CommandSchedule::close_open_ramps).
  void close_open_ramps(const std::string& why);
  void publish_tf(const core::Sample& s);
  void check_end_or_failure();
  void set_status(Status s);
  double achieved_real_time_factor() const;
  double running_wall_time_s() const;
  void publish_stats();
  void publish_clock(double t_s);

  void on_speed_command(const rotor_rub_msgs::SpeedCommand::ConstPtr& msg);
  void on_parameter_change(const rotor_rub_msgs::ParameterChange::ConstPtr& msg);
  void on_fault(const rotor_rub_msgs::Fault::ConstPtr& msg);
  bool on_inject_fault(rotor_rub_msgs::InjectFault::Request& req, rotor_rub_msgs::InjectFault::Response& res);
  // Checks a fault and queues it at its stamp; throws std::invalid_argument.
  double schedule_fault(const rotor_rub_msgs::Fault& msg);
  // Lockstep: at a period boundary, publishes lockstep_state and serves
  // callbacks until the controller's command for this time arrives (or the
  // timeout). Returns false if ROS shut down while waiting.
  bool lockstep_wait();
  bool on_reset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool on_pause(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool on_resume(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool on_step(rotor_rub_msgs::StepSimulation::Request& req, rotor_rub_msgs::StepSimulation::Response& res);
  void diagnose_solver(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void diagnose_pace(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void diagnose_contact(diagnostic_updater::DiagnosticStatusWrapper& stat);
  // A topic's publication rate (diagnostic_updater's frequency status),
  // but OK while not running, and for the keyphasor below a mark a second.
  void diagnose_rate(diagnostic_updater::FrequencyStatus& rate, bool per_revolution,
                     diagnostic_updater::DiagnosticStatusWrapper& stat);

  core::Scene scene_;
  NodeConfig config_;
  NodeOutput output_;  // publishing with recording
  std::unique_ptr<core::Simulation> sim_;
  Status status_ = Status::kRunning;
  core::CommandSchedule schedule_;  // speed commands, changes and faults by their stamps

  ros::Publisher state_pub_, event_pub_, stats_pub_, feedback_pub_, clock_pub_, marker_pub_, lockstep_pub_;
  ros::Publisher keyphasor_pub_, probes_pub_, change_feedback_pub_, tf_pub_, shaft_pub_;
  rotor_rub_msgs::ShaftDeflection shaft_msg_;  // its node positions set once (restart_simulation)
  std::vector<double> shaft_node_z_m_;
  ros::Subscriber change_sub_, fault_sub_;
  ros::ServiceServer fault_srv_;
  std::optional<ReconfigureServer> reconfigure_;
  // Publication rates as diagnostic_updater measures them (wall time, or
  // /clock's under use_sim_time), against what the pace makes expected.
  double state_rate_min_hz_ = 0.0, state_rate_max_hz_ = 0.0, probe_rate_min_hz_ = 0.0, probe_rate_max_hz_ = 0.0;
  double keyphasor_rate_min_hz_ = 0.0, keyphasor_rate_max_hz_ = 0.0;
  std::optional<diagnostic_updater::FrequencyStatus> state_rate_, probe_rate_, keyphasor_rate_;
  std::string tf_prefix_;     // the node's namespace and a slash ("" at the root): frames <ns>/stator, <ns>/rotor
  uint64_t revolutions_ = 0;  // keyphasor marks since the start or the last reset
  std::optional<core::ProbePair> probe_pair_;  // when probe_rate_hz > 0; its noise restarts with the run
  double lockstep_awaited_s_ = -1.0;           // the boundary a reply is awaited for
  bool lockstep_replied_ = false;
  uint64_t lockstep_timeouts_ = 0;
  ros::Subscriber command_sub_;
  ros::ServiceServer reset_srv_, pause_srv_, resume_srv_, step_srv_;
  RecordedDiagnostics diagnostics_;  // the tasks are diagnose_*
  std::optional<MarkerBuilder> markers_;

  rotor_rub_msgs::RotorState state_msg_;  // reused: no allocation per sample
  rotor_rub_msgs::ContactEvent event_msg_;
  core::Sample last_sample_;
  uint64_t states_published_ = 0, events_published_ = 0, commands_rejected_ = 0;
  double next_clock_s_ = 0.0, next_stats_s_ = 0.0, next_diag_s_ = 0.0, next_marker_s_ = 0.0, next_tf_s_ = 0.0;

  Pacing pacing_;  // in ros::WallTime seconds and simulated time
};

}  // namespace rotor_rub::ros_node
