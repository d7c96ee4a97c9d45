// The node's /diagnostics, recorded too: diagnostic_updater publishes
// /diagnostics itself and offers no copy of its message, so each task's last
// status is kept and the bag gets them as one array at the simulated time.
#pragma once

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "rotor_rub_sim/ros/node_output.hpp"

namespace rotor_rub::ros_node {

class RecordedDiagnostics {
 public:
  RecordedDiagnostics(ros::NodeHandle& nh, ros::NodeHandle& private_nh) : updater_(nh, private_nh) {}
  void set_hardware_id(const std::string& id) { updater_.setHardwareID(id); }
  // Registers a task; each runs once per update (a frequency status's window
  // moves when it runs), and what it said is kept for the bag.
  void add(const std::string& name, std::function<void(diagnostic_updater::DiagnosticStatusWrapper&)> task);
  // diagnostic_updater's own period (its wall-clock timer), between chunks.
  void update_if_due() { updater_.update(); }
  // Updates /diagnostics now and records the same statuses, named as the
  // updater names them ("<node>: <task>"), at the simulated time t_s.
  void update(double t_s, NodeOutput& output);

 private:
  diagnostic_updater::Updater updater_;
  // Each task's last status, in the order added.
  std::vector<std::pair<std::string, diagnostic_msgs::DiagnosticStatus>> last_;
};

}  // namespace rotor_rub::ros_node
