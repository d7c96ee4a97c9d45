// SimNode's private helpers shared by its units (sim_node.cpp: construction
// and the run loop; sim_node_output.cpp: the topics, the bag and tf;
// sim_node_commands.cpp: commands, changes, faults and services;
// sim_node_diagnostics.cpp): publishing with recording, and the output
// grids' ticks. Not installed.
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rotor_rub_sim/ros/sim_node.hpp"

namespace rotor_rub::ros_node {

// The first tick of a rate_hz grid strictly after t_s (a schedule in
// simulated time; the small margin absorbs k / rate rounding).
inline double next_tick(double t_s, double rate_hz) { return (std::floor(t_s * rate_hz + 1e-9) + 1.0) / rate_hz; }

template <class Msg>
void SimNode::record(const std::string& topic, const Msg& msg, double t_s, bool latching) {
  if (!recording_) return;
  try {
    bag_.write(topic, std::max(ros::Time().fromSec(std::max(t_s, 0.0)), ros::TIME_MIN), msg, latching);
  } catch (const std::runtime_error& e) {
    stop_recording(e.what(), t_s);
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

}  // namespace rotor_rub::ros_node
