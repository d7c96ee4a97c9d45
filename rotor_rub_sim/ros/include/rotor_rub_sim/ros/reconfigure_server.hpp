// A dynamic_reconfigure server (the protocol rqt_reconfigure and
// dynamic_reconfigure's clients speak: ~parameter_descriptions,
// ~parameter_updates, ~set_parameters) built at run time from the scene's key
// table: the live keys that act on this scene, with the table's ranges and
// descriptions, and the scene's start values as defaults. No .cfg file: the
// key table is the one source (a generated .cfg would be a second).
// A request's changed values become one live change (SimNode applies it at
// the simulated time reached, as an unstamped ParameterChange); the answer
// and ~parameter_updates carry the values in force afterwards (a refused
// change leaves the old ones, which rqt_reconfigure then shows).
#pragma once

#include <dynamic_reconfigure/Config.h>
#include <dynamic_reconfigure/Reconfigure.h>
#include <ros/ros.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::ros_node {

class ReconfigureServer {
 public:
  // Applies changed keys (scene key -> exact text); returns the scene in
  // force afterwards, and sets accepted to false when the change was refused.
  using Apply = std::function<core::Scene(const std::map<std::string, std::string>&, bool& accepted)>;

  ReconfigureServer(ros::NodeHandle& private_nh, const core::Scene& start, Apply apply);

  // Publishes the values in force on ~parameter_updates (after any change,
  // and after a reset).
  void publish_values(const core::Scene& scene);

  // The live keys offered (those that act on the scene), in table order.
  const std::vector<std::string>& keys() const { return keys_; }

 private:
  bool on_set_parameters(dynamic_reconfigure::Reconfigure::Request& req,
                         dynamic_reconfigure::Reconfigure::Response& res);
  dynamic_reconfigure::Config config_of(const core::Scene& scene) const;

  std::vector<std::string> keys_;
  Apply apply_;
  core::Scene current_;
  ros::Publisher descriptions_pub_, updates_pub_;
  ros::ServiceServer set_srv_;
};

}  // namespace rotor_rub::ros_node
