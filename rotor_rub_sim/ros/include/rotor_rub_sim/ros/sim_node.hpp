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
// real-time factor.
#pragma once

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "rotor_rub_msgs/ContactEvent.h"
#include "rotor_rub_msgs/Keyphasor.h"
#include "rotor_rub_msgs/ProbeSignals.h"
#include "rotor_rub_msgs/RotorState.h"
#include "rotor_rub_msgs/SolverStats.h"
#include "rotor_rub_msgs/SpeedCommand.h"
#include "rotor_rub_msgs/StepSimulation.h"
#include "rotor_rub_sim/core/probes.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "rotor_rub_sim/ros/bag_appender.hpp"
#include "rotor_rub_sim/ros/markers.hpp"
#include "rotor_rub_sim/ros/node_config.hpp"

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

 private:
  enum class Status : uint8_t { kRunning, kPaused, kFinished, kFailed };
  struct PendingCommand {
    double time_s;
    double target_rad_per_s;
    double accel_rad_per_s2;
  };

  bool wait_for_subscribers();
  void restart_simulation();
  // Advances to t_s, applying queued commands at their times on the way.
  void advance_to(double t_s);
  void apply_due_commands();
  void check_end_or_failure();
  void set_status(Status s);
  void anchor_pacing();
  double achieved_real_time_factor() const;
  double running_wall_time_s() const;
  void publish_stats();
  void publish_clock(double t_s);
  // Publishes and, when recording, writes the message into the bag at the
  // simulated time t_s (bags hold no time before 1 ns: t = 0 is filed there).
  template <class Msg>
  void publish(const ros::Publisher& pub, const Msg& msg, double t_s);
  template <class Msg>
  void record(const std::string& topic, const Msg& msg, double t_s, bool latching = false);
  // Hands the recording to the kernel every record_flush_period_s of wall time.
  void flush_recording_if_due();
  void stop_recording(const std::string& why, double t_s);

  void on_speed_command(const rotor_rub_msgs::SpeedCommand::ConstPtr& msg);
  // Lockstep: at a period boundary, publishes lockstep_state and serves
  // callbacks until the controller's command for this time arrives (or the
  // timeout). Returns false if ROS shut down while waiting.
  bool lockstep_wait();
  bool on_reset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool on_pause(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool on_resume(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res);
  bool on_step(rotor_rub_msgs::StepSimulation::Request& req, rotor_rub_msgs::StepSimulation::Response& res);
  // Updates /diagnostics now and records the same statuses into the bag.
  void update_diagnostics(double t_s);
  void diagnose_solver(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void diagnose_pace(diagnostic_updater::DiagnosticStatusWrapper& stat);
  void diagnose_contact(diagnostic_updater::DiagnosticStatusWrapper& stat);

  core::Scene scene_;
  NodeConfig config_;
  BagAppender bag_;
  bool recording_ = false;
  // header.seq of each published topic, as roscpp numbers it on the wire
  // (0, 1, ... per publisher), so that the bag's copy carries the same.
  std::map<std::string, uint32_t> published_seq_;
  ros::WallTime next_bag_flush_;
  std::unique_ptr<core::Simulation> sim_;
  Status status_ = Status::kRunning;
  std::vector<PendingCommand> pending_;  // sorted by time, stable in arrival order

  ros::Publisher state_pub_, event_pub_, stats_pub_, feedback_pub_, clock_pub_, marker_pub_, lockstep_pub_;
  ros::Publisher keyphasor_pub_, probes_pub_;
  uint64_t revolutions_ = 0;                   // keyphasor marks since the start or the last reset
  std::optional<core::ProbePair> probe_pair_;  // when probe_rate_hz > 0; its noise restarts with the run
  double lockstep_awaited_s_ = -1.0;           // the boundary a reply is awaited for
  bool lockstep_replied_ = false;
  uint64_t lockstep_timeouts_ = 0;
  // The last command applied (target, acceleration): a repeat changes
  // nothing, so it is not applied (the integration is not restarted).
  double applied_target_ = 0.0, applied_accel_ = 0.0;
  ros::Subscriber command_sub_;
  ros::ServiceServer reset_srv_, pause_srv_, resume_srv_, step_srv_;
  diagnostic_updater::Updater diagnostics_;
  std::optional<MarkerBuilder> markers_;

  rotor_rub_msgs::RotorState state_msg_;  // reused: no allocation per sample
  rotor_rub_msgs::ContactEvent event_msg_;
  core::Sample last_sample_;
  uint64_t states_published_ = 0, events_published_ = 0, commands_rejected_ = 0;
  double next_clock_s_ = 0.0, next_stats_s_ = 0.0, next_diag_s_ = 0.0, next_marker_s_ = 0.0;

  // Pacing and the achieved real-time factor (pauses and steps excluded).
  ros::WallTime pace_wall_anchor_;
  double pace_sim_anchor_s_ = 0.0;
  double run_wall_accum_s_ = 0.0, run_sim_accum_s_ = 0.0;
};

}  // namespace rotor_rub::ros_node
