#include "rotor_rub_sim/ros/reconfigure_server.hpp"

#include <dynamic_reconfigure/ConfigDescription.h>

#include "rotor_rub_sim/core/scene_keys.hpp"

namespace rotor_rub::ros_node {
namespace {

// dynamic_reconfigure's one group, as its generated servers name it.
dynamic_reconfigure::GroupState default_group() {
  dynamic_reconfigure::GroupState g;
  g.name = "Default";
  g.state = true;
  g.id = 0;
  g.parent = 0;
  return g;
}

dynamic_reconfigure::DoubleParameter double_parameter(const std::string& name, double value) {
  dynamic_reconfigure::DoubleParameter p;
  p.name = name;
  p.value = value;
  return p;
}

}  // namespace

ReconfigureServer::ReconfigureServer(ros::NodeHandle& private_nh, const core::Scene& start, Apply apply)
    : apply_(std::move(apply)), current_(start) {
  dynamic_reconfigure::ConfigDescription d;
  dynamic_reconfigure::Group group;
  group.name = "Default";
  group.type = "";
  group.id = 0;
  group.parent = 0;
  const auto values = core::scene_values(start);
  for (const auto& k : core::scene_keys()) {
    if (!k.live || !core::live_key_inert_reason(k.key, start).empty()) continue;
    keys_.push_back(k.key);
    dynamic_reconfigure::ParamDescription p;
    p.name = k.key;
    p.type = "double";
    p.level = 0;
    p.description = k.description + "; accepted: " + k.accepted;
    group.parameters.push_back(p);
    d.min.doubles.push_back(double_parameter(k.key, k.min_value));
    d.max.doubles.push_back(double_parameter(k.key, k.max_value));
    d.dflt.doubles.push_back(double_parameter(k.key, std::stod(values.at(k.key))));
  }
  d.groups.push_back(group);
  for (auto* c : {&d.min, &d.max, &d.dflt}) c->groups.push_back(default_group());
  // Latched, as dynamic_reconfigure's own server: a client that connects
  // later gets the description and the values in force.
  descriptions_pub_ = private_nh.advertise<dynamic_reconfigure::ConfigDescription>("parameter_descriptions", 1, true);
  updates_pub_ = private_nh.advertise<dynamic_reconfigure::Config>("parameter_updates", 1, true);
  descriptions_pub_.publish(d);
  publish_values(start);
  set_srv_ = private_nh.advertiseService("set_parameters", &ReconfigureServer::on_set_parameters, this);
}

dynamic_reconfigure::Config ReconfigureServer::config_of(const core::Scene& scene) const {
  dynamic_reconfigure::Config c;
  const auto values = core::scene_values(scene);
  for (const auto& key : keys_) c.doubles.push_back(double_parameter(key, std::stod(values.at(key))));
  c.groups.push_back(default_group());
  return c;
}

void ReconfigureServer::publish_values(const core::Scene& scene) {
  current_ = scene;
  updates_pub_.publish(config_of(scene));
}

bool ReconfigureServer::on_set_parameters(dynamic_reconfigure::Reconfigure::Request& req,
                                          dynamic_reconfigure::Reconfigure::Response& res) {
  // Only what differs from the values in force is a change (clients send
  // the whole configuration, or only what the user edited); a key this
  // server does not offer is passed on, and refused with its reason.
  const auto values = core::scene_values(current_);
  std::map<std::string, std::string> changes;
  for (const auto& p : req.config.doubles) {
    const auto now = values.find(p.name);
    if (now == values.end() || std::stod(now->second) != p.value) changes[p.name] = core::exact_text(p.value);
  }
  for (const auto& p : req.config.ints) changes[p.name] = std::to_string(p.value);
  for (const auto& p : req.config.strs) changes[p.name] = p.value;
  for (const auto& p : req.config.bools) changes[p.name] = p.value ? "true" : "false";
  bool accepted = true;
  if (!changes.empty()) current_ = apply_(changes, accepted);
  res.config = config_of(current_);
  updates_pub_.publish(res.config);
  // A refused change fails the call, so that the caller sees it (dynparam
  // exits non-zero with the service's error; the reason is in the node's log
  // and on parameter_change_feedback): a reply with the old value looked like
  // success (test_live_changes.py, test_shell_tools.py).
  return accepted;
}

}  // namespace rotor_rub::ros_node
