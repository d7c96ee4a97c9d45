// The node's publishing with recording: a message goes to its topic and,
// while a bag is open (record_bag), into the bag at its simulated time, with
// the header.seq roscpp gave the wire copy. A bag that fails stops the
// recording and keeps what it holds (complete chunks stay readable); the
// node runs on.
#pragma once

#include <ros/ros.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>

#include "rotor_rub_sim/ros/bag_appender.hpp"

namespace rotor_rub::ros_node {

class NodeOutput {
 public:
  // Opens the bag at path (throws std::runtime_error naming the node
  // parameter record_bag); the kernel gets it every flush_period_s of wall time.
  void open(const std::string& path, double flush_period_s);
  bool recording() const { return recording_; }

  // Publishes msg and, when recording, writes it at the simulated time t_s
  // (bags hold no time before 1 ns: t = 0 is filed there).
  template <class Msg>
  void publish(const ros::Publisher& pub, const Msg& msg, double t_s);
  // Writes msg into the bag only (the node's inputs, /diagnostics).
  template <class Msg>
  void record(const std::string& topic, const Msg& msg, double t_s, bool latching = false);

  // Hands the recording to the kernel if flush_period_s has passed.
  void flush_if_due(double t_s);
  // Closes the bag with its index (complete: no reindex needed).
  void close(double t_s);

 private:
  void stop(const std::string& why, double t_s);

  BagAppender bag_;
  std::string path_;
  bool recording_ = false;
  double flush_period_s_ = 0.0;
  ros::WallTime next_flush_;
  // header.seq of each published topic, as roscpp numbers it on the wire
  // (0, 1, ... per publisher), so that the bag's copy carries the same.
  std::map<std::string, uint32_t> published_seq_;
};

template <class Msg>
void NodeOutput::record(const std::string& topic, const Msg& msg, double t_s, bool latching) {
  if (!recording_) return;
  try {
    bag_.write(topic, std::max(ros::Time().fromSec(std::max(t_s, 0.0)), ros::TIME_MIN), msg, latching);
  } catch (const std::runtime_error& e) {
    stop(e.what(), t_s);
  }
}

template <class Msg>
void NodeOutput::publish(const ros::Publisher& pub, const Msg& msg, double t_s) {
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
