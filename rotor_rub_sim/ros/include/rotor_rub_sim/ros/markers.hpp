// RViz markers of the rotor-stator pair: the clearance circle (where the
// rotor centre touches the stator, radius C about the stator centre), the
// rotor centre, the stator centre, the orbit trail of the rotor centre and the
// contact force arrow. Model lengths are multiplied by marker_scale so that a
// millimetre orbit is visible at RViz's default zoom.
#pragma once

#include <visualization_msgs/MarkerArray.h>

#include <vector>

#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/run_types.hpp"
#include "rotor_rub_sim/ros/node_config.hpp"

namespace rotor_rub::ros_node {

class MarkerBuilder {
 public:
  MarkerBuilder(const core::ModelParameters& model, const NodeConfig& config);

  // Every state sample enters the orbit trail (a ring buffer, no allocation).
  void add(const core::Sample& s);
  void clear();
  // After a live change: the clearance drawn is the model's.
  void set_model(const core::ModelParameters& model) { model_ = model; }
  // The markers for the latest sample added.
  const visualization_msgs::MarkerArray& build(const ros::Time& stamp);

 private:
  core::ModelParameters model_;
  double scale_;
  double force_scale_m_per_N_;
  std::vector<core::Vec2> trail_;  // ring of rotor positions [m]
  std::size_t trail_next_ = 0;
  std::size_t trail_size_ = 0;
  core::Sample latest_;
  visualization_msgs::MarkerArray array_;
};

// A flexible rotor's deflected shaft (namespace "shaft"): its centreline
// through the nodes and the nodes as spheres, the rub station red. The
// lateral displacements are multiplied by marker_scale, the positions along
// the shaft are not; the station sits at z = 0, where the orbit is drawn.
visualization_msgs::MarkerArray shaft_markers(const core::ShaftSample& s, const std::vector<double>& node_z_m,
                                              int station_node, const NodeConfig& config, const ros::Time& stamp);

}  // namespace rotor_rub::ros_node
