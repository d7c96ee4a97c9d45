#include "rotor_rub_sim/ros/recorded_diagnostics.hpp"

#include <diagnostic_msgs/DiagnosticArray.h>

#include <algorithm>

namespace rotor_rub::ros_node {

void RecordedDiagnostics::add(const std::string& name,
                              std::function<void(diagnostic_updater::DiagnosticStatusWrapper&)> task) {
  last_.emplace_back(name, diagnostic_msgs::DiagnosticStatus());
  const std::size_t slot = last_.size() - 1;
  updater_.add(name, [this, slot, task](diagnostic_updater::DiagnosticStatusWrapper& stat) {
    task(stat);
    last_[slot].second = stat;
  });
}

void RecordedDiagnostics::update(double t_s, NodeOutput& output) {
  updater_.force_update();
  if (!output.recording()) return;
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = ros::Time().fromSec(std::max(t_s, 0.0));
  for (const auto& [name, status] : last_) {
    array.status.push_back(status);
    array.status.back().name = ros::this_node::getName().substr(1) + ": " + name;
  }
  output.record("/diagnostics", array, t_s);
}

}  // namespace rotor_rub::ros_node
