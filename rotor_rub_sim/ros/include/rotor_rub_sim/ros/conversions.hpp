// Core types to and from messages. No logic: field by field, SI units kept.
#pragma once

#include <ros/node_handle.h>

#include <map>
#include <string>

#include "rotor_rub_msgs/ContactEvent.h"
#include "rotor_rub_msgs/RotorState.h"
#include "rotor_rub_msgs/SolverStats.h"
#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::ros_node {

// sample_index is k (t = k / output_rate_hz), so that a subscriber or a bag
// reader detects a lost message as a gap (roscpp overwrites header.seq).
void to_msg(const core::Sample& s, uint64_t sample_index, const std::string& frame_id, rotor_rub_msgs::RotorState& msg);
void to_msg(const core::ContactEvent& e, const std::string& frame_id, rotor_rub_msgs::ContactEvent& msg);
void to_msg(const core::RunStats& stats, const core::Scene& scene, rotor_rub_msgs::SolverStats& msg);

// And back, for tools that read bags.
core::Sample from_msg(const rotor_rub_msgs::RotorState& msg);
core::ContactEvent from_msg(const rotor_rub_msgs::ContactEvent& msg);

// Every parameter in the node's private namespace, as text (numbers with 17
// significant digits, booleans as true/false). Throws core::SceneError for a
// parameter of a type no key accepts (a list, a dictionary, binary).
std::map<std::string, std::string> private_params_as_text(const ros::NodeHandle& private_nh);

}  // namespace rotor_rub::ros_node
