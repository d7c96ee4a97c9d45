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
#include "tf2_msgs/TFMessage.h"

namespace rotor_rub::ros_node {
namespace {

// The first tick of a rate_hz grid strictly after t_s (a schedule in
// simulated time; the small margin absorbs k / rate rounding).
double next_tick(double t_s, double rate_hz) { return (std::floor(t_s * rate_hz + 1e-9) + 1.0) / rate_hz; }

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

  diagnostics_.setHardwareID(std::string("rotor_rub_sim/") + core::to_string(scene_.solver.method));
  add_diagnostic("solver", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) { diagnose_solver(stat); });
  add_diagnostic("real-time factor",
                 [this](diagnostic_updater::DiagnosticStatusWrapper& stat) { diagnose_pace(stat); });
  add_diagnostic("contact", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) { diagnose_contact(stat); });
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
  add_diagnostic("state topic status", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) {
    diagnose_rate(*state_rate_, false, stat);
  });
  if (probes_pub_) {
    rates(scene_.probes.rate_hz, probe_rate_min_hz_, probe_rate_max_hz_);
    probe_rate_.emplace(diagnostic_updater::FrequencyStatusParam(&probe_rate_min_hz_, &probe_rate_max_hz_, tolerance));
    add_diagnostic("probes topic status", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) {
      diagnose_rate(*probe_rate_, false, stat);
    });
  }
  // Once per revolution: from standstill (0) to the largest speed a command may ask.
  keyphasor_rate_max_hz_ =
      pace > 0.0 ? scene_.speed.max_speed_rad_per_s / (2.0 * M_PI) * pace : std::numeric_limits<double>::infinity();
  keyphasor_rate_.emplace(
      diagnostic_updater::FrequencyStatusParam(&keyphasor_rate_min_hz_, &keyphasor_rate_max_hz_, tolerance));
  add_diagnostic("keyphasor topic status", [this](diagnostic_updater::DiagnosticStatusWrapper& stat) {
    diagnose_rate(*keyphasor_rate_, true, stat);
  });
  if (!config_.record_bag.empty()) {
    try {
      bag_.open(config_.record_bag);
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(std::string("node parameter 'record_bag': ") + e.what() +
                               "; accepted: a writable file path, or empty for none");
    }
    recording_ = true;
    next_bag_flush_ = ros::WallTime::now() + ros::WallDuration(config_.record_flush_period_s);
  }
  restart_simulation();
}

template <class Msg>
void SimNode::record(const std::string& topic, const Msg& msg, double t_s, bool latching) {
  if (!recording_) return;
  try {
    bag_.write(topic, std::max(ros::Time().fromSec(std::max(t_s, 0.0)), ros::TIME_MIN), msg, latching);
  } catch (const std::runtime_error& e) {
    stop_recording(e.what(), t_s);
  }
}

void SimNode::stop_recording(const std::string& why, double t_s) {
  // Keep what is recorded (complete chunks stay readable) and say so once.
  ROS_ERROR("recording to '%s' stopped at t = %.6f s: %s", config_.record_bag.c_str(), t_s, why.c_str());
  recording_ = false;
}

void SimNode::add_diagnostic(const std::string& name,
                             std::function<void(diagnostic_updater::DiagnosticStatusWrapper&)> task) {
  // Each task runs once per update (a frequency status's window moves when
  // it runs): the updater runs it, and the bag records what it said.
  recorded_diagnostics_.emplace_back(name, diagnostic_msgs::DiagnosticStatus());
  const std::size_t slot = recorded_diagnostics_.size() - 1;
  diagnostics_.add(name, [this, slot, task](diagnostic_updater::DiagnosticStatusWrapper& stat) {
    task(stat);
    recorded_diagnostics_[slot].second = stat;
  });
}

void SimNode::update_diagnostics(double t_s) {
  diagnostics_.force_update();
  if (!recording_) return;
  // diagnostic_updater publishes /diagnostics itself and offers no copy of
  // its message: the bag gets the statuses its tasks gave, named as it names
  // them ("<node>: <task>"), stamped with the simulated time.
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = ros::Time().fromSec(std::max(t_s, 0.0));
  for (const auto& [name, status] : recorded_diagnostics_) {
    array.status.push_back(status);
    array.status.back().name = ros::this_node::getName().substr(1) + ": " + name;
  }
  record("/diagnostics", array, t_s);
}

void SimNode::flush_recording_if_due() {
  if (!recording_) return;
  const ros::WallTime now = ros::WallTime::now();
  if (now < next_bag_flush_) return;
  next_bag_flush_ = now + ros::WallDuration(config_.record_flush_period_s);
  try {
    bag_.flush();
  } catch (const std::runtime_error& e) {
    stop_recording(e.what(), sim_->time());
  }
}

template <class Msg>
void SimNode::publish(const ros::Publisher& pub, const Msg& msg, double t_s) {
  pub.publish(msg);
  if constexpr (ros::message_traits::HasHeader<Msg>::value) {
    // roscpp stamps header.seq on the wire copy only: the bag's copy gets
    // the same number.
    const uint32_t seq = published_seq_[pub.getTopic()]++;
    if (recording_) {
      Msg copy = msg;
      copy.header.seq = seq;
      record(pub.getTopic(), copy, t_s, pub.isLatched());
    }
  } else {
    record(pub.getTopic(), msg, t_s, pub.isLatched());
  }
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
  run_wall_accum_s_ = run_sim_accum_s_ = 0.0;
  anchor_pacing();
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
    flush_recording_if_due();
    if (status_ != Status::kRunning) {
      const bool over = status_ == Status::kFinished || status_ == Status::kFailed;
      if (over && config_.end_action == EndAction::kExit) break;
      // Idle (paused, finished, failed): keep /diagnostics alive at the
      // updater's own period, so a monitor that connects late sees the state.
      diagnostics_.update();
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
      const ros::WallTime due =
          pace_wall_anchor_ + ros::WallDuration((t_next - pace_sim_anchor_s_) / config_.real_time_factor);
      const ros::WallTime now = ros::WallTime::now();
      if (due > now) (due - now).sleep();
    }
    advance_to(t_next);
    if (config_.lockstep_period_s > 0.0 && status_ == Status::kRunning && !lockstep_wait()) break;
  }
  int exit_status = 0;
  if (sim_->failure()) exit_status = core::exit_status(sim_->failure()->failure_class);
  close_open_ramps("the node stopped");  // answered, and recorded, before the bag closes
  if (recording_) {
    try {
      bag_.close();  // the index: the bag is complete, no reindex needed
      ROS_INFO("recorded %lu messages into '%s'", static_cast<unsigned long>(bag_.messages_written()),
               config_.record_bag.c_str());
    } catch (const std::runtime_error& e) {
      stop_recording(e.what(), sim_->time());
    }
  }
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
  publish(lockstep_pub_, state_msg_, sim_->time());  // the state at the boundary (just sampled)
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
  // Wall time spent waiting is the controller's, not the simulator's.
  anchor_pacing();
  return ros::ok();
}

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
    publish(change_feedback_pub_, fb, sim_->time());
    applied = applied || a.accepted;
  }
  if (applied) {
    if (reconfigure_) reconfigure_->publish_values(sim_->scene());
    if (markers_) markers_->set_model(sim_->scene().model);  // the bore drawn where it now is
  }
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
  if (was_running && s != Status::kRunning) {
    run_wall_accum_s_ += (ros::WallTime::now() - pace_wall_anchor_).toSec();
    run_sim_accum_s_ += sim_->time() - pace_sim_anchor_s_;
  }
  status_ = s;
  if (s == Status::kRunning) anchor_pacing();
  publish_stats();
  update_diagnostics(sim_->time());
}

void SimNode::anchor_pacing() {
  pace_wall_anchor_ = ros::WallTime::now();
  pace_sim_anchor_s_ = sim_->time();
}

double SimNode::running_wall_time_s() const {
  double w = run_wall_accum_s_;
  if (status_ == Status::kRunning) w += (ros::WallTime::now() - pace_wall_anchor_).toSec();
  return w;
}

double SimNode::achieved_real_time_factor() const {
  double sim = run_sim_accum_s_;
  if (status_ == Status::kRunning) sim += sim_->time() - pace_sim_anchor_s_;
  const double wall = running_wall_time_s();
  return wall > 0.0 ? sim / wall : 0.0;
}

// ---- Observer: samples and events become messages --------------------------

void SimNode::on_sample(const core::Sample& s) {
  last_sample_ = s;
  const auto index = static_cast<uint64_t>(std::llround(s.t_s * scene_.output_rate_hz));
  to_msg(s, index, config_.frame_id, state_msg_);
  publish(state_pub_, state_msg_, s.t_s);
  state_rate_->tick();
  ++states_published_;
  if (tf_pub_ && s.t_s >= next_tf_s_) {
    publish_tf(s);
    next_tf_s_ = next_tick(s.t_s, config_.tf_rate_hz);
  }
  if (config_.publish_clock && s.t_s >= next_clock_s_) {
    publish_clock(s.t_s);
    next_clock_s_ = next_tick(s.t_s, config_.clock_rate_hz);
  }
  if (markers_) {
    markers_->add(s);
    if (s.t_s >= next_marker_s_) {
      publish(marker_pub_, markers_->build(state_msg_.header.stamp), s.t_s);
      next_marker_s_ = next_tick(s.t_s, config_.marker_rate_hz);
    }
  }
  if (s.t_s >= next_stats_s_) {
    publish_stats();
    next_stats_s_ = next_tick(s.t_s, config_.stats_rate_hz);
  }
  if (s.t_s >= next_diag_s_) {
    update_diagnostics(s.t_s);
    next_diag_s_ = next_tick(s.t_s, config_.diagnostics_rate_hz);
  }
}

void SimNode::on_event(const core::ContactEvent& e) {
  to_msg(e, config_.frame_id, event_msg_);
  publish(event_pub_, event_msg_, e.t_s);
  ++events_published_;
}

void SimNode::on_keyphasor(const core::Sample& s) {
  rotor_rub_msgs::Keyphasor msg;
  msg.header.stamp = ros::Time().fromSec(s.t_s);
  msg.header.frame_id = config_.frame_id;
  msg.time = s.t_s;
  msg.revolution = ++revolutions_;
  msg.speed = s.drive.speed_rad_per_s;
  publish(keyphasor_pub_, msg, s.t_s);
  keyphasor_rate_->tick();
}

void SimNode::on_probe_sample(const core::Sample& s) {
  const core::ProbeReading r = probe_pair_->read(s);
  rotor_rub_msgs::ProbeSignals msg;
  msg.header.stamp = ros::Time().fromSec(r.t_s);
  msg.header.frame_id = config_.frame_id;
  msg.time = r.t_s;
  msg.x = r.x_V;
  msg.y = r.y_V;
  msg.x_displacement = r.x_m;
  msg.y_displacement = r.y_m;
  publish(probes_pub_, msg, r.t_s);
  probe_rate_->tick();
}

void SimNode::on_shaft_sample(const core::ShaftSample& s) {
  shaft_msg_.header.stamp.fromSec(s.t_s);
  shaft_msg_.time = s.t_s;
  for (std::size_t i = 0; i < shaft_msg_.nodes.size(); ++i) {
    shaft_msg_.nodes[i].x = s.node_displacement_m[i].x();
    shaft_msg_.nodes[i].y = s.node_displacement_m[i].y();
  }
  publish(shaft_pub_, shaft_msg_, s.t_s);
  if (markers_) {
    publish(marker_pub_, shaft_markers(s, shaft_node_z_m_, shaft_msg_.station_node, config_, shaft_msg_.header.stamp),
            s.t_s);
  }
}

void SimNode::publish_tf(const core::Sample& s) {
  // The stator's centre, and the rotor's geometric centre turned by the spin
  // angle phi about z (its x axis points at the keyphasor's notch), in
  // frame_id, stamped in simulated time as every header.
  tf2_msgs::TFMessage msg;
  msg.transforms.resize(2);
  for (auto& t : msg.transforms) {
    t.header.stamp.fromSec(s.t_s);
    t.header.frame_id = config_.frame_id;
    t.transform.rotation.w = 1.0;
  }
  msg.transforms[0].child_frame_id = tf_prefix_ + "stator";
  msg.transforms[0].transform.translation.x = s.kin.stator_pos.x();
  msg.transforms[0].transform.translation.y = s.kin.stator_pos.y();
  msg.transforms[1].child_frame_id = tf_prefix_ + "rotor";
  msg.transforms[1].transform.translation.x = s.kin.rotor_pos.x();
  msg.transforms[1].transform.translation.y = s.kin.rotor_pos.y();
  msg.transforms[1].transform.rotation.z = std::sin(0.5 * s.drive.angle_rad);
  msg.transforms[1].transform.rotation.w = std::cos(0.5 * s.drive.angle_rad);
  publish(tf_pub_, msg, s.t_s);
}

void SimNode::publish_clock(double t_s) {
  // Time zero means "no time yet" to a node on simulated time: skip it.
  if (!(t_s > 0.0)) return;
  rosgraph_msgs::Clock c;
  c.clock.fromSec(t_s);
  publish(clock_pub_, c, t_s);
}

void SimNode::publish_stats() {
  rotor_rub_msgs::SolverStats msg;
  to_msg(sim_->stats(), scene_, msg);
  msg.header.stamp.fromSec(sim_->time());
  msg.header.frame_id = config_.frame_id;
  msg.sim_time = sim_->time();
  msg.wall_time = running_wall_time_s();
  msg.real_time_factor = achieved_real_time_factor();
  msg.states_published = states_published_;
  msg.events_published = events_published_;
  switch (status_) {
    case Status::kRunning:
      msg.status = rotor_rub_msgs::SolverStats::RUNNING;
      break;
    case Status::kPaused:
      msg.status = rotor_rub_msgs::SolverStats::PAUSED;
      break;
    case Status::kFinished:
      msg.status = rotor_rub_msgs::SolverStats::FINISHED;
      break;
    case Status::kFailed:
      msg.status = rotor_rub_msgs::SolverStats::FAILED;
      break;
  }
  if (const auto& f = sim_->failure()) {
    msg.failure_class = core::to_string(f->failure_class);
    msg.failure_message = f->message;
  }
  publish(stats_pub_, msg, sim_->time());
}

// ---- Callbacks: messages and services become core calls --------------------

void SimNode::on_speed_command(const rotor_rub_msgs::SpeedCommand::ConstPtr& msg) {
  record(command_sub_.getTopic(), *msg, sim_->time());  // the inputs too, for replay
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
  publish(feedback_pub_, fb, sim_->time());
}

void SimNode::on_parameter_change(const rotor_rub_msgs::ParameterChange::ConstPtr& msg) {
  record(change_sub_.getTopic(), *msg, sim_->time());  // the inputs too, for replay
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
  record(fault_sub_.getTopic(), *msg, sim_->time());
  try {
    schedule_fault(*msg);
  } catch (const std::exception& e) {  // invalid_argument: refused; anything else must not escape a callback
    refuse_change({}, msg->fault_id, fault_source(msg->kind), e.what());
  }
}

bool SimNode::on_inject_fault(rotor_rub_msgs::InjectFault::Request& req, rotor_rub_msgs::InjectFault::Response& res) {
  // Recorded as the topic's message would be: a bag shows every fault asked.
  record(fault_sub_.getTopic(), req.fault, sim_->time());
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

void SimNode::diagnose_solver(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  using diagnostic_msgs::DiagnosticStatus;
  if (const auto& f = sim_->failure()) {
    stat.summaryf(DiagnosticStatus::ERROR, "method failed (%s) at t = %.9g s: %s", core::to_string(f->failure_class),
                  f->time_s, f->message.c_str());
  } else {
    const char* state = status_ == Status::kRunning ? "running" : status_ == Status::kPaused ? "paused" : "finished";
    stat.summaryf(DiagnosticStatus::OK, "%s at t = %.6f s", state, sim_->time());
  }
  const auto& st = sim_->stats();
  stat.add("method", core::to_string(scene_.solver.method));
  stat.add("integrator", core::to_string(core::effective_integrator(scene_)));
  stat.add("simulated time [s]", sim_->time());
  stat.add("steps", st.steps);
  stat.add("rejected steps", st.rejected_steps);
  stat.add("rhs evaluations", st.rhs_evals);
  stat.add("root iterations", st.root_iterations);
  stat.add("restarts", st.restarts);
}

void SimNode::diagnose_pace(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  using diagnostic_msgs::DiagnosticStatus;
  const double achieved = achieved_real_time_factor();
  const double wanted = config_.real_time_factor;
  // Below 90 % of a requested pace the node lags the wall clock.
  if (status_ == Status::kRunning && wanted > 0.0 && running_wall_time_s() > 1.0 && achieved < 0.9 * wanted) {
    stat.summaryf(DiagnosticStatus::WARN, "lagging: real-time factor %.2f of %.2f requested", achieved, wanted);
  } else {
    stat.summaryf(DiagnosticStatus::OK, "real-time factor %.2f (requested %s)", achieved,
                  wanted > 0.0 ? std::to_string(wanted).c_str() : "as fast as possible");
  }
  stat.add("achieved real-time factor", achieved);
  stat.add("requested real-time factor", wanted);
  stat.add("states published", states_published_);
}

void SimNode::diagnose_rate(diagnostic_updater::FrequencyStatus& rate, bool per_revolution,
                            diagnostic_updater::DiagnosticStatusWrapper& stat) {
  using diagnostic_msgs::DiagnosticStatus;
  // diagnostic_updater's frequency status is an ERROR with no message in its
  // window: right for a topic that should flow, wrong for a paused node or a
  // keyphasor below one mark a second.
  const double pace = ros::Time::isSimTime() || !(config_.real_time_factor > 0.0) ? 1.0 : config_.real_time_factor;
  if (status_ != Status::kRunning) {
    stat.summary(DiagnosticStatus::OK, "not running: no publications expected");
  } else if (per_revolution && last_sample_.drive.speed_rad_per_s * pace < 2.0 * M_PI) {
    stat.summary(DiagnosticStatus::OK, "under one revolution a second: not judged");
  } else {
    rate.run(stat);
  }
}

void SimNode::diagnose_contact(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  using diagnostic_msgs::DiagnosticStatus;
  stat.summary(DiagnosticStatus::OK, last_sample_.in_contact ? "in contact (rub)" : "free flight");
  stat.add("in contact", last_sample_.in_contact);
  stat.add("normal force [N]", last_sample_.normal_force_N);
  stat.add("gap [m]", -last_sample_.penetration_m);
  const auto& st = sim_->stats();
  stat.add("touchdowns", st.touchdowns);
  stat.add("liftoffs", st.liftoffs);
  stat.add("grazes", st.grazes);
}

}  // namespace rotor_rub::ros_node
