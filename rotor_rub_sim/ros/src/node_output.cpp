#include "rotor_rub_sim/ros/node_output.hpp"

namespace rotor_rub::ros_node {

void NodeOutput::open(const std::string& path, double flush_period_s) {
  try {
    bag_.open(path);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("node parameter 'record_bag': ") + e.what() +
                             "; accepted: a writable file path, or empty for none");
  }
  path_ = path;
  recording_ = true;
  flush_period_s_ = flush_period_s;
  next_flush_ = ros::WallTime::now() + ros::WallDuration(flush_period_s_);
}

void NodeOutput::flush_if_due(double t_s) {
  if (!recording_) return;
  const ros::WallTime now = ros::WallTime::now();
  if (now < next_flush_) return;
  next_flush_ = now + ros::WallDuration(flush_period_s_);
  try {
    bag_.flush();
  } catch (const std::runtime_error& e) {
    stop(e.what(), t_s);
  }
}

void NodeOutput::close(double t_s) {
  if (!recording_) return;
  try {
    bag_.close();
    recording_ = false;
    ROS_INFO("recorded %lu messages into '%s'", static_cast<unsigned long>(bag_.messages_written()), path_.c_str());
  } catch (const std::runtime_error& e) {
    stop(e.what(), t_s);
  }
}

void NodeOutput::stop(const std::string& why, double t_s) {
  // Keep what is recorded and say so once.
  ROS_ERROR("recording to '%s' stopped at t = %.6f s: %s", path_.c_str(), t_s, why.c_str());
  recording_ = false;
}

}  // namespace rotor_rub::ros_node
