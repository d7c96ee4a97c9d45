#include "rotor_rub_sim/ros/sim_node.hpp"

#include <ros/callback_queue.h>
#include <rosgraph_msgs/Clock.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "rotor_rub_msgs/ParameterChangeFeedback.h"
#include "rotor_rub_msgs/SpeedCommandFeedback.h"
#include "rotor_rub_sim/core/solver_registry.hpp"
#include "rotor_rub_sim/ros/conversions.hpp"
#include "sim_node_io.hpp"
#include "tf2_msgs/TFMessage.h"

namespace rotor_rub::ros_node {

SimNode::SimNode(ros::NodeHandle& nh, ros::NodeHandle& private_nh, const NodeSetup& setup)
    : scene_(setup.scene), config_(setup.config), schedule_(setup.scene.output_rate_hz), diagnostics_(nh, private_nh) {
  // Topics and services are relative to the node's namespace (as ROS users
  // expect: `ns` and `remap` place several simulators in one graph, and a
  // monitor in the same namespace finds "state" without knowing the node's
  // name); parameters stay private; /clock is global by definition.
  const uint32_t q = static_cast<uint32_t>(config_.publish_queue_size);
  state_pub_ = nh.advertise<rotor_rub_msgs::RotorState>("state", q);
  event_pub_ = nh.advertise<rotor_rub_msgs::ContactEvent>("contact_events", q);
  stats_pub_ = nh.advertise<rotor_rub_msgs::SolverStats>("solver_stats", q, /*latch=*/true);
  feedback_pub_ = nh.advertise<rotor_rub_msgs::SpeedCommandFeedback>("speed_command_feedback", q);
  keyphasor_pub_ = nh.advertise<rotor_rub_msgs::Keyphasor>("keyphasor", q);
  if (scene_.probes.rate_hz > 0.0) probes_pub_ = nh.advertise<rotor_rub_msgs::ProbeSignals>("probes", q);
  if (core::rotor_kind(scene_) == core::RotorKind::kFlexible && config_.shaft_rate_hz > 0.0) {
    shaft_pub_ = nh.advertise<rotor_rub_msgs::ShaftDeflection>("shaft", q);
  }
  if (config_.publish_clock) clock_pub_ = nh.advertise<rosgraph_msgs::Clock>("/clock", q);
  if (config_.marker_rate_hz > 0.0) {
    marker_pub_ = nh.advertise<visualization_msgs::MarkerArray>("markers", 10);
    markers_.emplace(scene_.model, config_);
  }
  // Commands are served in arrival order; a deep queue so a burst is judged
  // command by command rather than dropped unseen.
  command_sub_ = nh.subscribe("speed_command", 10000, &SimNode::on_speed_command, this);
  if (config_.lockstep_period_s > 0.0) {
    lockstep_pub_ = nh.advertise<rotor_rub_msgs::RotorState>("lockstep_state", q);
  }
  change_feedback_pub_ = nh.advertise<rotor_rub_msgs::ParameterChangeFeedback>("parameter_change_feedback", q);
  change_sub_ = nh.subscribe("parameter_change", 10000, &SimNode::on_parameter_change, this);
  fault_sub_ = nh.subscribe("faults", 10000, &SimNode::on_fault, this);
  fault_srv_ = nh.advertiseService("inject_fault", &SimNode::on_inject_fault, this);
  if (config_.tf_rate_hz > 0.0) tf_pub_ = nh.advertise<tf2_msgs::TFMessage>("/tf", 100);
  tf_prefix_ = nh.getNamespace() == "/" ? "" : nh.getNamespace().substr(1) + "/";
  reconfigure_.emplace(private_nh, scene_, [this](const std::map<std::string, std::string>& changes, bool& accepted) {
    std::vector<core::ChangeAnswer> answers;  // unstamped: applied now, or refused
    schedule_.change_parameters(*sim_, 0.0, changes, 0, "dynamic_reconfigure", answers);
    accepted = !answers.empty() && answers.back().accepted;
    answer(answers);
    check_end_or_failure();
    return sim_->scene();
  });
  reset_srv_ = nh.advertiseService("reset", &SimNode::on_reset, this);
  pause_srv_ = nh.advertiseService("pause", &SimNode::on_pause, this);
  resume_srv_ = nh.advertiseService("resume", &SimNode::on_resume, this);
  step_srv_ = nh.advertiseService("step", &SimNode::on_step, this);

  diagnostics_.set_hardware_id(std::string("rotor_rub_sim/") + core::to_string(scene_.solver.method));
  diagnostics_.add("solver", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) { diagnose_solver(stat); });
  diagnostics_.add("real-time factor",
                   [this](diagnostic_updater::DiagnosticStatusWrapper& stat) { diagnose_pace(stat); });
  diagnostics_.add("contact", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) { diagnose_contact(stat); });
  // The rates expected of state, probes and keyphasor: the simulated rate
  // times the pace (under use_sim_time the updater's clock is the
  // simulated one: the pace is 1); as fast as possible, no bound.
  const double pace = ros::Time::isSimTime() ? 1.0 : config_.real_time_factor;
  const double tolerance = 0.1;  // diagnostic_updater's default band
  auto rates = [&](double rate_hz, double& lo, double& hi) {
    lo = pace > 0.0 ? rate_hz * pace : 0.0;
    hi = pace > 0.0 ? rate_hz * pace : std::numeric_limits<double>::infinity();
  };
  rates(scene_.output_rate_hz, state_rate_min_hz_, state_rate_max_hz_);
  state_rate_.emplace(diagnostic_updater::FrequencyStatusParam(&state_rate_min_hz_, &state_rate_max_hz_, tolerance));
  diagnostics_.add("state topic status", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) {
    diagnose_rate(*state_rate_, false, stat);
  });
  if (probes_pub_) {
    rates(scene_.probes.rate_hz, probe_rate_min_hz_, probe_rate_max_hz_);
    probe_rate_.emplace(diagnostic_updater::FrequencyStatusParam(&probe_rate_min_hz_, &probe_rate_max_hz_, tolerance));
    diagnostics_.add("probes topic status", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) {
      diagnose_rate(*probe_rate_, false, stat);
    });
  }
  // Once per revolution: from standstill (0) to the largest speed a command may ask.
  keyphasor_rate_max_hz_ =
      pace > 0.0 ? scene_.speed.max_speed_rad_per_s / (2.0 * M_PI) * pace : std::numeric_limits<double>::infinity();
  keyphasor_rate_.emplace(
      diagnostic_updater::FrequencyStatusParam(&keyphasor_rate_min_hz_, &keyphasor_rate_max_hz_, tolerance));
  diagnostics_.add("keyphasor topic status", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) {
    diagnose_rate(*keyphasor_rate_, true, stat);
  });
  if (!config_.record_bag.empty()) output_.open(config_.record_bag, config_.record_flush_period_s);
  restart_simulation();
}

void SimNode::restart_simulation() {
  sim_ = std::make_unique<core::Simulation>(scene_);
  lockstep_awaited_s_ = -1.0;
  if (config_.end_action == EndAction::kContinue) sim_->set_end_time(std::numeric_limits<double>::infinity());
  schedule_.clear();
  states_published_ = events_published_ = 0;
  next_clock_s_ = next_stats_s_ = next_diag_s_ = next_marker_s_ = next_tf_s_ = 0.0;
  if (reconfigure_) reconfigure_->publish_values(scene_);  // a reset restores the scene's values
  last_sample_ = core::Sample{};
  revolutions_ = 0;
  if (scene_.probes.rate_hz > 0.0) probe_pair_.emplace(scene_.probes);  // the same noise again
  pacing_.clear();
  pacing_.anchor(ros::WallTime::now().toSec(), sim_->time());
  if (markers_) {
    markers_->clear();
    markers_->set_model(scene_.model);
  }
  shaft_node_z_m_ = sim_->shaft_node_z_m();
  shaft_msg_.station_node = sim_->shaft_station_node();
  shaft_msg_.header.frame_id = config_.frame_id;
  shaft_msg_.nodes.resize(shaft_node_z_m_.size());
  for (std::size_t i = 0; i < shaft_node_z_m_.size(); ++i) shaft_msg_.nodes[i].z = shaft_node_z_m_[i];
}

bool SimNode::wait_for_subscribers() {
  std::vector<std::pair<const ros::Publisher*, uint32_t>> needs;
  const auto all = static_cast<uint32_t>(config_.wait_for_subscribers);
  if (all > 0) {
    for (const auto* p : {&state_pub_, &event_pub_, &stats_pub_, &feedback_pub_}) needs.emplace_back(p, all);
    if (config_.publish_clock) needs.emplace_back(&clock_pub_, all);
    if (markers_) needs.emplace_back(&marker_pub_, all);
  }
  if (config_.wait_for_state_subscribers > 0) {
    needs.emplace_back(&state_pub_, std::max(all, static_cast<uint32_t>(config_.wait_for_state_subscribers)));
    if (config_.lockstep_period_s > 0.0) needs.emplace_back(&lockstep_pub_, 1u);
  }
  if (needs.empty()) return true;
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(config_.wait_timeout_s);
  ROS_INFO("waiting for subscribers (wait_for_subscribers %u, wait_for_state_subscribers %d)", all,
           config_.wait_for_state_subscribers);
  while (ros::ok()) {
    std::string missing;
    for (const auto& [p, needed] : needs) {
      if (p->getNumSubscribers() < needed) missing += " " + p->getTopic();
    }
    // In lockstep the controller must also be heard: a publisher on speed_command.
    if (config_.lockstep_period_s > 0.0 && config_.wait_for_state_subscribers > 0 &&
        command_sub_.getNumPublishers() == 0) {
      missing += " (no publisher on " + command_sub_.getTopic() + ")";
    }
    if (missing.empty()) return true;
    if (ros::WallTime::now() > deadline) {
      ROS_FATAL("after wait_timeout_s = %g s these topics still lack subscribers:%s", config_.wait_timeout_s,
                missing.c_str());
      return false;
    }
    ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(0.01));
  }
  return false;
}

int SimNode::run() {
  if (!wait_for_subscribers()) return 1;
  const core::Simulation::Reduction reduction = sim_->reduction();
  const std::string rotor = core::rotor_kind(scene_) == core::RotorKind::kJeffcott
                                ? std::string("the Jeffcott rotor")
                                : "the flexible rotor " + scene_.rotor.file + ", " +
                                      core::to_string(reduction.planar_modes, reduction.truncation);
  ROS_INFO(
      "%s the scene (%s) with method %s (%s, rtol %g, atol %g): end_time_s %g, state at %g Hz, "
      "real_time_factor %g, end_action %s",
      config_.start_paused ? "paused at t = 0 s (call the resume or step service) before simulating" : "simulating",
      rotor.c_str(), core::to_string(scene_.solver.method), core::to_string(core::effective_integrator(scene_)),
      scene_.solver.rtol, scene_.solver.atol, scene_.end_time_s, scene_.output_rate_hz, config_.real_time_factor,
      to_string(config_.end_action));
  set_status(config_.start_paused ? Status::kPaused : Status::kRunning);
  // Chunks of 1 ms of simulated time, or of one output period when that is
  // longer (never shorter than either), ending on multiples of the chunk;
  // in lockstep a chunk also ends at the next control-period boundary.
  // Callbacks are served between chunks, and pacing sleeps per chunk.
  const double chunk_s = std::max(1.0 / scene_.output_rate_hz, 1e-3);
  ros::CallbackQueue& queue = *ros::getGlobalCallbackQueue();
  while (ros::ok()) {
    output_.flush_if_due(sim_->time());
    if (status_ != Status::kRunning) {
      const bool over = status_ == Status::kFinished || status_ == Status::kFailed;
      if (over && config_.end_action == EndAction::kExit) break;
      // Idle (paused, finished, failed): keep /diagnostics alive at the
      // updater's own period, so a monitor that connects late sees the state.
      diagnostics_.update_if_due();
      queue.callAvailable(ros::WallDuration(0.05));
      continue;
    }
    queue.callAvailable();
    if (status_ != Status::kRunning) continue;
    const double k = std::floor(sim_->time() / chunk_s);
    double t_next = (k + 1.0) * chunk_s;
    if (t_next <= sim_->time()) t_next = (k + 2.0) * chunk_s;
    if (config_.lockstep_period_s > 0.0) {
      // Boundaries on the output grid: index arithmetic, not float division.
      const long per = std::lround(config_.lockstep_period_s * scene_.output_rate_hz);
      const long done = std::lround(sim_->time() * scene_.output_rate_hz);
      const double boundary = static_cast<double>((done / per + 1) * per) / scene_.output_rate_hz;
      t_next = std::min(t_next, boundary);
    }
    if (config_.real_time_factor > 0.0) {
      const ros::WallTime due(pacing_.due_wall_s(t_next, config_.real_time_factor));
      const ros::WallTime now = ros::WallTime::now();
      if (due > now) (due - now).sleep();
    }
    advance_to(t_next);
    if (config_.lockstep_period_s > 0.0 && status_ == Status::kRunning && !lockstep_wait()) break;
  }
  int exit_status = 0;
  if (sim_->failure()) exit_status = core::exit_status(sim_->failure()->failure_class);
  close_open_ramps("the node stopped");  // answered, and recorded, before the bag closes
  output_.close(sim_->time());
  if (ros::ok()) {
    // Let subscribers (a recorder) drain their queues before the
    // connections close: roscpp offers no delivery acknowledgement.
    const ros::WallTime until = ros::WallTime::now() + ros::WallDuration(config_.exit_linger_s);
    while (ros::ok() && ros::WallTime::now() < until) queue.callAvailable(ros::WallDuration(0.02));
  }
  return exit_status;
}

void SimNode::advance_to(double t_s) {
  apply_due_commands();
  while (!sim_->failure() && sim_->time() < t_s) {
    const double before = sim_->time();
    const double stop = std::min(t_s, schedule_.next_time_s());
    if (!sim_->advance_to(stop, *this)) break;
    apply_due_commands();
    if (sim_->time() <= before) break;  // the scene's end
  }
  check_end_or_failure();
}

bool SimNode::lockstep_wait() {
  const long per = std::lround(config_.lockstep_period_s * scene_.output_rate_hz);
  const long done = std::lround(sim_->time() * scene_.output_rate_hz);
  if (done % per != 0) return true;  // not at a boundary (a command or the end cut the chunk)
  lockstep_awaited_s_ = sim_->time();
  lockstep_replied_ = false;
  output_.publish(lockstep_pub_, state_msg_, sim_->time());  // the state at the boundary (just sampled)
  // Wall time spent waiting is the controller's, not the simulator's.
  pacing_.close_stretch(ros::WallTime::now().toSec(), sim_->time());
  ros::CallbackQueue& queue = *ros::getGlobalCallbackQueue();
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(config_.lockstep_timeout_s);
  while (ros::ok() && !lockstep_replied_) {
    if (ros::WallTime::now() > deadline) {
      ++lockstep_timeouts_;
      ROS_WARN_THROTTLE(1.0,
                        "lockstep: no speed command stamped t >= %.6f s within lockstep_timeout_s = %g s; going on "
                        "(this run is no longer reproducible; %lu timeouts)",
                        lockstep_awaited_s_, config_.lockstep_timeout_s,
                        static_cast<unsigned long>(lockstep_timeouts_));
      break;
    }
    queue.callAvailable(ros::WallDuration(0.001));
  }
  pacing_.anchor(ros::WallTime::now().toSec(), sim_->time());
  return ros::ok();
}

void SimNode::check_end_or_failure() {
  if (status_ == Status::kFailed || status_ == Status::kFinished) return;
  if (const auto& f = sim_->failure()) {
    ROS_ERROR("method %s failed (%s) at t = %.9g s: %s", core::to_string(scene_.solver.method),
              core::to_string(f->failure_class), f->time_s, f->message.c_str());
    close_open_ramps("the method failed");
    set_status(Status::kFailed);
  } else if (config_.end_action != EndAction::kContinue && sim_->time() >= scene_.end_time_s) {
    close_open_ramps("the run reached end_time_s");
    set_status(Status::kFinished);
    ROS_INFO("reached end_time_s = %g s: %lu states, %lu events published; achieved real-time factor %.2f",
             scene_.end_time_s, static_cast<unsigned long>(states_published_),
             static_cast<unsigned long>(events_published_), achieved_real_time_factor());
  }
}

void SimNode::set_status(Status s) {
  const bool was_running = status_ == Status::kRunning;
  if (was_running && s != Status::kRunning) pacing_.close_stretch(ros::WallTime::now().toSec(), sim_->time());
  status_ = s;
  if (s == Status::kRunning) pacing_.anchor(ros::WallTime::now().toSec(), sim_->time());
  publish_stats();
  diagnostics_.update(sim_->time(), output_);
}

double SimNode::running_wall_time_s() const {
  return pacing_.running_wall_s(ros::WallTime::now().toSec(), status_ == Status::kRunning);
}

double SimNode::achieved_real_time_factor() const {
  return pacing_.achieved_real_time_factor(ros::WallTime::now().toSec(), sim_->time(), status_ == Status::kRunning);
}

// ---- Observer: samples and events become messages --------------------------

}  // namespace rotor_rub::ros_node
