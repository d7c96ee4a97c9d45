// SimNode's inputs: speed commands, parameter changes and faults into the
// schedule (core::CommandSchedule) and their answers, and the services.
#include <ros/ros.h>
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
namespace {

// "fault:<kind>", or "fault" for a kind out of range.
std::string fault_source(uint8_t kind) {
  for (const core::FaultKind k : core::kAllFaultKinds) {
    if (static_cast<uint8_t>(k) == kind) return std::string("fault:") + core::to_string(k);
  }
  return "fault";
}

core::FaultKind fault_kind(uint8_t kind) {
  for (const core::FaultKind k : core::kAllFaultKinds) {
    if (static_cast<uint8_t>(k) == kind) return k;
  }
  throw std::invalid_argument("fault kind " + std::to_string(kind) + " is out of range; accepted: 0 (BLADE_LOSS) to " +
                              std::to_string(static_cast<int>(core::FaultKind::kSupportLoosening)) +
                              " (SUPPORT_LOOSENING)");
}

}  // namespace

void SimNode::apply_due_commands() {
  std::vector<core::ChangeAnswer> answers;
  schedule_.apply_due(*sim_, answers);
  answer(answers);
}

void SimNode::close_open_ramps(const std::string& why) {
  std::vector<core::ChangeAnswer> answers;
  schedule_.close_open_ramps(*sim_, why, answers);
  answer(answers);
}

void SimNode::refuse_change(const std::map<std::string, std::string>& changes, uint32_t id, const std::string& source,
                            const std::string& reason) {
  core::ChangeAnswer a;
  a.id = id;
  a.source = source;
  a.changes = changes;
  for (const auto& c : changes) a.from[c.first] = std::numeric_limits<double>::quiet_NaN();
  a.start_s = a.end_s = sim_->time();
  a.reason = reason;
  answer({a});
}

void SimNode::answer(const std::vector<core::ChangeAnswer>& answers) {
  bool applied = false;
  for (const core::ChangeAnswer& a : answers) {
    rotor_rub_msgs::ParameterChangeFeedback fb;
    fb.header.stamp.fromSec(sim_->time());
    fb.header.frame_id = config_.frame_id;
    fb.change_id = a.id;
    fb.source = a.source;
    std::string listed;
    for (const auto& [key, value] : a.changes) {
      fb.keys.push_back(key);
      double v = std::numeric_limits<double>::quiet_NaN();
      try {
        v = std::stod(value);
      } catch (const std::exception&) {  // a non-number that was refused: NaN in the echo
      }
      fb.values.push_back(v);
      const auto from = a.from.find(key);
      fb.from_values.push_back(from == a.from.end() ? std::numeric_limits<double>::quiet_NaN() : from->second);
      listed += (listed.empty() ? "" : ", ") + key + " = " + value;
    }
    fb.accepted = a.accepted;
    fb.effective_time = a.start_s;
    fb.end_time = a.end_s;
    fb.steps = a.steps;
    fb.reason = a.reason;
    // Every answer is logged once (a ramp once, at its end).
    if (a.accepted && !a.reason.empty()) listed += " (" + a.reason + ")";
    if (a.accepted && a.steps > 1) {
      ROS_INFO("parameter change %u from %s applied from t = %.6f s to %.6f s in %u steps: %s", a.id, a.source.c_str(),
               a.start_s, a.end_s, a.steps, listed.c_str());
    } else if (a.accepted) {
      ROS_INFO("parameter change %u from %s applied at t = %.6f s: %s", a.id, a.source.c_str(), a.start_s,
               listed.c_str());
    } else {
      ROS_WARN("parameter change %u from %s refused at t = %.6f s, simulation unchanged: %s", a.id, a.source.c_str(),
               a.end_s, a.reason.c_str());
    }
    output_.publish(change_feedback_pub_, fb, sim_->time());
    applied = applied || a.accepted;
  }
  if (applied) {
    if (reconfigure_) reconfigure_->publish_values(sim_->scene());
    if (markers_) markers_->set_model(sim_->scene().model);  // the bore drawn where it now is
  }
}

void SimNode::on_speed_command(const rotor_rub_msgs::SpeedCommand::ConstPtr& msg) {
  output_.record(command_sub_.getTopic(), *msg, sim_->time());  // the inputs too, for replay
  const double t_cmd = msg->header.stamp.toSec();
  const core::SpeedAnswer a = schedule_.command_speed(*sim_, t_cmd, msg->target_speed, msg->acceleration_limit);
  rotor_rub_msgs::SpeedCommandFeedback fb;
  fb.header.stamp.fromSec(sim_->time());
  fb.header.frame_id = config_.frame_id;
  fb.command_id = msg->command_id;
  fb.target_speed = msg->target_speed;
  fb.acceleration_limit = a.accel_rad_per_s2;
  fb.accepted = a.accepted;
  fb.effective_time = a.effective_time_s;
  fb.reason = a.reason;
  if (a.accepted) {
    if (lockstep_awaited_s_ >= 0.0 && t_cmd >= lockstep_awaited_s_ - 0.5 / scene_.output_rate_hz) {
      lockstep_replied_ = true;  // the controller's command for this period (stamps are rounded to ns)
    }
    // The feedback answers every command; the log names accepted ones at
    // most once a second (a controller may command every few ms).
    ROS_INFO_THROTTLE(1.0, "speed command %u accepted: %g rad/s at %g rad/s^2 from t = %.6f s", msg->command_id,
                      msg->target_speed, a.accel_rad_per_s2, a.effective_time_s);
  } else {
    // Every command gets its feedback; the log gets at most one line a
    // second, so that a flood of bad commands cannot flood /rosout too.
    ++commands_rejected_;
    ROS_WARN_THROTTLE(1.0, "speed command rejected, simulation unchanged: %s (%lu rejected so far)", a.reason.c_str(),
                      static_cast<unsigned long>(commands_rejected_));
  }
  output_.publish(feedback_pub_, fb, sim_->time());
}

void SimNode::on_parameter_change(const rotor_rub_msgs::ParameterChange::ConstPtr& msg) {
  output_.record(change_sub_.getTopic(), *msg, sim_->time());  // the inputs too, for replay
  std::map<std::string, std::string> changes;
  std::string refused;
  for (std::size_t i = 0; i < msg->keys.size() && i < msg->values.size(); ++i) {
    if (changes.count(msg->keys[i]) != 0) refused = "key '" + msg->keys[i] + "' is given twice";
    changes[msg->keys[i]] = core::exact_text(msg->values[i]);
  }
  if (msg->keys.size() != msg->values.size()) {
    refused = "keys and values differ in number (" + std::to_string(msg->keys.size()) + " keys, " +
              std::to_string(msg->values.size()) + " values)";
  }
  if (!refused.empty()) {
    refuse_change(changes, msg->change_id, msg->source, refused);
    return;
  }
  std::vector<core::ChangeAnswer> answers;
  schedule_.change_parameters(*sim_, msg->header.stamp.toSec(), changes, msg->change_id, msg->source, answers);
  answer(answers);
  check_end_or_failure();  // a restart under a change may fail as a step may
}

double SimNode::schedule_fault(const rotor_rub_msgs::Fault& msg) {
  core::Fault f;
  f.kind = fault_kind(msg.kind);
  f.magnitude = msg.magnitude;
  f.phase_rad = msg.phase;
  f.duration_s = msg.duration;
  f.node = msg.node;
  std::vector<core::ChangeAnswer> answers;
  const double first_s = schedule_.inject_fault(*sim_, msg.header.stamp.toSec(), f, msg.fault_id, answers);
  ROS_INFO("fault %u (%s, magnitude %g, phase %g rad, duration %g s, node %d) scheduled at t = %.6f s", msg.fault_id,
           fault_source(msg.kind).c_str(), f.magnitude, f.phase_rad, f.duration_s, f.node, first_s);
  answer(answers);  // one due now applied at once, as an unstamped change
  check_end_or_failure();
  return first_s;
}

void SimNode::on_fault(const rotor_rub_msgs::Fault::ConstPtr& msg) {
  output_.record(fault_sub_.getTopic(), *msg, sim_->time());
  try {
    schedule_fault(*msg);
  } catch (const std::exception& e) {  // invalid_argument: refused; anything else must not escape a callback
    refuse_change({}, msg->fault_id, fault_source(msg->kind), e.what());
  }
}

bool SimNode::on_inject_fault(rotor_rub_msgs::InjectFault::Request& req, rotor_rub_msgs::InjectFault::Response& res) {
  // Recorded as the topic's message would be: a bag shows every fault asked.
  output_.record(fault_sub_.getTopic(), req.fault, sim_->time());
  try {
    res.effective_time = schedule_fault(req.fault);
    res.accepted = true;
  } catch (const std::exception& e) {
    res.accepted = false;
    res.reason = e.what();
    refuse_change({}, req.fault.fault_id, fault_source(req.fault.kind), e.what());
  }
  return true;
}

bool SimNode::on_reset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  const bool keep_running = status_ == Status::kRunning;
  close_open_ramps("the node was reset");
  restart_simulation();
  status_ = Status::kPaused;  // counters were restarted: no running time to close
  set_status(keep_running ? Status::kRunning : Status::kPaused);
  res.success = true;
  res.message =
      keep_running ? "reset to t = 0 s, running" : "reset to t = 0 s, paused (call the resume or step service)";
  ROS_INFO("reset: %s", res.message.c_str());
  return true;
}

bool SimNode::on_pause(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  if (status_ == Status::kRunning) set_status(Status::kPaused);
  res.success = status_ == Status::kPaused;
  res.message = res.success ? "paused at t = " + std::to_string(sim_->time()) + " s"
                            : "not running (finished or failed); call the reset service";
  ROS_INFO("pause: %s", res.message.c_str());
  return true;
}

bool SimNode::on_resume(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
  if (status_ == Status::kPaused) set_status(Status::kRunning);
  res.success = status_ == Status::kRunning;
  res.message = res.success ? "running from t = " + std::to_string(sim_->time()) + " s"
                            : "the run has finished or failed at t = " + std::to_string(sim_->time()) +
                                  " s; call the reset service";
  ROS_INFO("resume: %s", res.message.c_str());
  return true;
}

bool SimNode::on_step(rotor_rub_msgs::StepSimulation::Request& req, rotor_rub_msgs::StepSimulation::Response& res) {
  if (!std::isfinite(req.duration) || req.duration <= 0.0) {
    res.success = false;
    res.message = "duration " + std::to_string(req.duration) + " s is out of range; accepted: (0, inf)";
  } else if (status_ != Status::kPaused) {
    res.success = false;
    res.message = status_ == Status::kRunning ? "step needs a paused simulation; call the pause service first"
                                              : "the run has finished or failed; call the reset service";
  } else {
    advance_to(sim_->time() + req.duration);
    res.success = !sim_->failure();
    res.message = res.success ? "stepped" : "the method failed: " + sim_->failure()->message;
    publish_stats();
  }
  res.sim_time = sim_->time();
  return true;
}

// ---- Diagnostics -------------------------------------------------------------

}  // namespace rotor_rub::ros_node
