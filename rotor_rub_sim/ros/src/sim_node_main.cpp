// rotor_rub_sim_node: the simulator as a ROS node. Every private parameter is
// a scene key (config/scene_template.yaml) or a node key (NodeConfig); they
// are validated once here, and a bad one ends the node with exit status 2.
#include <ros/ros.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_options.hpp"
#include "package_paths.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/ros/conversions.hpp"
#include "rotor_rub_sim/ros/sim_node.hpp"

namespace {

// A relative rotor_file that is not there from the node's directory names a
// file of the package's config/: rosparam loads a shipped scene
// (config/seal_rub_runup.yaml: rotors/seal_rub.yaml) without its directory,
// which the headless runner resolves against.
void resolve_rotor_file(std::map<std::string, std::string>& values) {
  const auto it = values.find("rotor_file");
  if (it == values.end() || it->second.empty() || std::filesystem::path(it->second).is_absolute() ||
      std::filesystem::exists(it->second)) {
    return;
  }
  try {
    it->second = rotor_rub::cli::find_package_file("config/" + it->second);
  } catch (const std::runtime_error&) {
    // Left as given: the scene's check names the key and the file.
  }
}

}  // namespace

int main(int argc, char** argv) {
  namespace cli = rotor_rub::cli;
  // ROS's own arguments (__name:=x, __ns:=/y, _param:=value, topic:=other)
  // are ros::init's; CLI11 sees the rest, so an unknown --flag is an error.
  // Neither --help nor --list-keys needs a master.
  std::vector<std::string> own_args;
  ros::removeROSArgs(argc, argv, own_args);
  std::vector<const char*> own_argv;
  for (const auto& a : own_args) own_argv.push_back(a.c_str());
  bool list_keys = false;
  CLI::App app(
      "The rotor-to-stator rub simulator as a ROS node. Its private parameters are the scene keys "
      "(rotor_rub_run --list-keys, config/scene_template.yaml) and the node keys (--list-keys, "
      "config/node_template.yaml); a bad one ends the node with exit status 2. ROS arguments (__name:=NAME, "
      "__ns:=NS, _key:=value, topic:=other) pass through to ros::init.",
      "rotor_rub_sim_node");
  // --list-keys: the node's own keys, in rotor_rub_run --list-keys' format
  // (scripts/gen_scene_template.py makes config/node_template.yaml of it).
  app.add_flag("--list-keys", list_keys,
               "print the node's own keys (not the scene's) with default, accepted range and meaning; exit");
  app.footer(
      "Exit status: 0 ended or shut down; 1 subscribers missing after wait_timeout_s; 2 bad input (usage, a "
      "parameter, setup); a failed run ends with its class's status, as in rotor_rub_run (3 stalled, 4 diverged, "
      "5 not converged, 7 timed out, 8 invariant violated).");
  cli::parse_or_exit(app, static_cast<int>(own_argv.size()), own_argv.data());
  if (list_keys) {
    for (const auto& k : rotor_rub::ros_node::node_keys()) {
      std::printf("%-34s default %-10s accepted %s\n    %s\n", k.key.c_str(),
                  k.default_value.empty() ? "\"\"" : k.default_value.c_str(), k.accepted.c_str(),
                  k.description.c_str());
    }
    return 0;
  }
  ros::init(argc, argv, "rotor_rub_sim");
  ros::NodeHandle nh;
  ros::NodeHandle private_nh("~");
  rotor_rub::ros_node::NodeSetup setup;
  try {
    std::map<std::string, std::string> values = rotor_rub::ros_node::private_params_as_text(private_nh);
    resolve_rotor_file(values);
    setup = rotor_rub::ros_node::node_setup_from_values(values);
  } catch (const rotor_rub::core::SceneError& e) {
    // Parameters outlive a node on the master: an unknown key may be a typo
    // in this launch's YAML or one left over from an earlier run.
    const bool unknown = e.kind() == rotor_rub::core::SceneError::Kind::kUnknownKey;
    ROS_FATAL("bad parameter, not started: %s%s%s%s", e.what(),
              unknown ? "; the node reads every parameter under " : "",
              unknown ? private_nh.getNamespace().c_str() : "",
              unknown ? " on the master: a key left there by an earlier run stays until `rosparam delete` (the "
                        "package's launch files clear the node's parameters at start)"
                      : "");
    return 2;
  }
  try {
    rotor_rub::ros_node::SimNode node(nh, private_nh, setup);
    return node.run();
  } catch (const std::runtime_error& e) {
    ROS_FATAL("not started: %s", e.what());
    return 2;
  }
}
