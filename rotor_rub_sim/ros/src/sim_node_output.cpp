// SimNode's output: samples, events, marks, probes and the shaft to their
// topics and the bag, tf, /clock and the solver's statistics.
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

void SimNode::on_sample(const core::Sample& s) {
  last_sample_ = s;
  const auto index = static_cast<uint64_t>(std::llround(s.t_s * scene_.output_rate_hz));
  to_msg(s, index, config_.frame_id, state_msg_);
  output_.publish(state_pub_, state_msg_, s.t_s);
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
      output_.publish(marker_pub_, markers_->build(state_msg_.header.stamp), s.t_s);
      next_marker_s_ = next_tick(s.t_s, config_.marker_rate_hz);
    }
  }
  if (s.t_s >= next_stats_s_) {
    publish_stats();
    next_stats_s_ = next_tick(s.t_s, config_.stats_rate_hz);
  }
  if (s.t_s >= next_diag_s_) {
    diagnostics_.update(s.t_s, output_);
    next_diag_s_ = next_tick(s.t_s, config_.diagnostics_rate_hz);
  }
}

void SimNode::on_event(const core::ContactEvent& e) {
  to_msg(e, config_.frame_id, event_msg_);
  output_.publish(event_pub_, event_msg_, e.t_s);
  ++events_published_;
}

void SimNode::on_keyphasor(const core::Sample& s) {
  rotor_rub_msgs::Keyphasor msg;
  msg.header.stamp = ros::Time().fromSec(s.t_s);
  msg.header.frame_id = config_.frame_id;
  msg.time = s.t_s;
  msg.revolution = ++revolutions_;
  msg.speed = s.drive.speed_rad_per_s;
  output_.publish(keyphasor_pub_, msg, s.t_s);
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
  output_.publish(probes_pub_, msg, r.t_s);
  probe_rate_->tick();
}

void SimNode::on_shaft_sample(const core::ShaftSample& s) {
  shaft_msg_.header.stamp.fromSec(s.t_s);
  shaft_msg_.time = s.t_s;
  for (std::size_t i = 0; i < shaft_msg_.nodes.size(); ++i) {
    shaft_msg_.nodes[i].x = s.node_displacement_m[i].x();
    shaft_msg_.nodes[i].y = s.node_displacement_m[i].y();
  }
  output_.publish(shaft_pub_, shaft_msg_, s.t_s);
  if (markers_) {
    output_.publish(marker_pub_,
                    shaft_markers(s, shaft_node_z_m_, shaft_msg_.station_node, config_, shaft_msg_.header.stamp),
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
  output_.publish(tf_pub_, msg, s.t_s);
}

void SimNode::publish_clock(double t_s) {
  // Time zero means "no time yet" to a node on simulated time: skip it.
  if (!(t_s > 0.0)) return;
  rosgraph_msgs::Clock c;
  c.clock.fromSec(t_s);
  output_.publish(clock_pub_, c, t_s);
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
  output_.publish(stats_pub_, msg, sim_->time());
}

// ---- Callbacks: messages and services become core calls --------------------

}  // namespace rotor_rub::ros_node
