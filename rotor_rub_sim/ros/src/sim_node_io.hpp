// SimNode's private helper shared by its units (sim_node.cpp: construction
// and the run loop; sim_node_output.cpp: the topics and tf;
// sim_node_commands.cpp: commands, changes, faults and services;
// sim_node_diagnostics.cpp): the output grids' ticks. Not installed.
#pragma once

#include <cmath>

#include "rotor_rub_sim/ros/sim_node.hpp"

namespace rotor_rub::ros_node {

// The first tick of a rate_hz grid strictly after t_s (a schedule in
// simulated time; the small margin absorbs k / rate rounding).
inline double next_tick(double t_s, double rate_hz) { return (std::floor(t_s * rate_hz + 1e-9) + 1.0) / rate_hz; }

}  // namespace rotor_rub::ros_node
