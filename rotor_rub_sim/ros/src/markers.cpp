#include "rotor_rub_sim/ros/markers.hpp"

#include <cmath>

namespace rotor_rub::ros_node {
namespace {

constexpr int kCircleSegments = 96;
enum MarkerId { kClearanceCircle = 0, kRotor, kStator, kOrbitTrail, kContactForce, kMarkerCount };

visualization_msgs::Marker make_marker(int id, int type, const std::string& frame_id, float r, float g, float b) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame_id;
  m.ns = "rotor_rub";
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.color.r = r;
  m.color.g = g;
  m.color.b = b;
  m.color.a = 1.0f;
  return m;
}

geometry_msgs::Point point(const core::Vec2& p, double scale) {
  geometry_msgs::Point q;
  q.x = p.x() * scale;
  q.y = p.y() * scale;
  q.z = 0.0;
  return q;
}

}  // namespace

MarkerBuilder::MarkerBuilder(const core::ModelParameters& model, const NodeConfig& config)
    : model_(model),
      scale_(config.marker_scale),
      force_scale_m_per_N_(config.marker_force_scale_m_per_N),
      trail_(static_cast<std::size_t>(config.orbit_trail_samples), core::Vec2::Zero()) {
  using visualization_msgs::Marker;
  const double c = model_.clearance_m * scale_;
  array_.markers.resize(kMarkerCount);
  array_.markers[kClearanceCircle] =
      make_marker(kClearanceCircle, Marker::LINE_STRIP, config.frame_id, 0.6f, 0.6f, 0.6f);
  array_.markers[kClearanceCircle].scale.x = 0.01 * c;
  array_.markers[kClearanceCircle].points.resize(kCircleSegments + 1);
  array_.markers[kRotor] = make_marker(kRotor, Marker::SPHERE, config.frame_id, 0.1f, 0.4f, 1.0f);
  array_.markers[kRotor].scale.x = array_.markers[kRotor].scale.y = array_.markers[kRotor].scale.z = 0.08 * c;
  array_.markers[kStator] = make_marker(kStator, Marker::SPHERE, config.frame_id, 0.5f, 0.5f, 0.5f);
  array_.markers[kStator].scale.x = array_.markers[kStator].scale.y = array_.markers[kStator].scale.z = 0.05 * c;
  array_.markers[kOrbitTrail] = make_marker(kOrbitTrail, Marker::LINE_STRIP, config.frame_id, 0.2f, 0.8f, 0.2f);
  array_.markers[kOrbitTrail].scale.x = 0.005 * c;
  array_.markers[kOrbitTrail].points.reserve(trail_.size());
  array_.markers[kContactForce] = make_marker(kContactForce, Marker::ARROW, config.frame_id, 1.0f, 0.2f, 0.1f);
  array_.markers[kContactForce].scale.x = 0.02 * c;  // shaft diameter
  array_.markers[kContactForce].scale.y = 0.05 * c;  // head diameter
  array_.markers[kContactForce].points.resize(2);
}

void MarkerBuilder::add(const core::Sample& s) {
  latest_ = s;
  trail_[trail_next_] = s.kin.rotor_pos;
  trail_next_ = (trail_next_ + 1) % trail_.size();
  trail_size_ = std::min(trail_size_ + 1, trail_.size());
}

void MarkerBuilder::clear() {
  trail_next_ = trail_size_ = 0;
  latest_ = core::Sample{};
}

const visualization_msgs::MarkerArray& MarkerBuilder::build(const ros::Time& stamp) {
  for (auto& m : array_.markers) m.header.stamp = stamp;
  const core::Vec2 stator = latest_.kin.stator_pos;
  auto& circle = array_.markers[kClearanceCircle];
  for (int i = 0; i <= kCircleSegments; ++i) {
    const double a = 2.0 * M_PI * i / kCircleSegments;
    circle.points[i] = point(stator + model_.clearance_m * core::Vec2(std::cos(a), std::sin(a)), scale_);
  }
  array_.markers[kRotor].pose.position = point(latest_.kin.rotor_pos, scale_);
  array_.markers[kStator].pose.position = point(stator, scale_);
  auto& trail = array_.markers[kOrbitTrail];
  trail.points.clear();
  const std::size_t start = (trail_next_ + trail_.size() - trail_size_) % trail_.size();
  for (std::size_t i = 0; i < trail_size_; ++i)
    trail.points.push_back(point(trail_[(start + i) % trail_.size()], scale_));
  // RViz rejects a line strip with fewer than two points.
  if (trail.points.size() < 2) trail.points.assign(2, point(latest_.kin.rotor_pos, scale_));
  // The force arrow: from the contact point on the clearance circle, along
  // the contact force on the rotor; hidden (DELETE) out of contact.
  auto& arrow = array_.markers[kContactForce];
  if (latest_.in_contact && latest_.normal_force_N > 0.0) {
    arrow.action = visualization_msgs::Marker::ADD;
    const core::Vec2 d = latest_.kin.rotor_pos - stator;
    const double n = d.norm();
    const core::Vec2 contact = n > 0.0 ? core::Vec2(stator + d * (model_.clearance_m / n)) : stator;
    arrow.points[0] = point(contact, scale_);
    arrow.points[1] = arrow.points[0];  // the arrow's length is in RViz metres, unscaled
    arrow.points[1].x += latest_.contact_force_on_rotor_N.x() * force_scale_m_per_N_;
    arrow.points[1].y += latest_.contact_force_on_rotor_N.y() * force_scale_m_per_N_;
  } else {
    arrow.action = visualization_msgs::Marker::DELETE;
  }
  return array_;
}

visualization_msgs::MarkerArray shaft_markers(const core::ShaftSample& s, const std::vector<double>& node_z_m,
                                              int station_node, const NodeConfig& config, const ros::Time& stamp) {
  using visualization_msgs::Marker;
  const double z0 = node_z_m.at(static_cast<std::size_t>(station_node));
  const double length_m = node_z_m.back() - node_z_m.front();
  visualization_msgs::MarkerArray array;
  array.markers.push_back(make_marker(0, Marker::LINE_STRIP, config.frame_id, 0.3f, 0.3f, 0.9f));
  array.markers.push_back(make_marker(1, Marker::SPHERE_LIST, config.frame_id, 0.9f, 0.9f, 0.9f));
  Marker& line = array.markers[0];
  Marker& nodes = array.markers[1];
  line.scale.x = 0.005 * length_m;
  nodes.scale.x = nodes.scale.y = nodes.scale.z = 0.02 * length_m;
  for (std::size_t i = 0; i < s.node_displacement_m.size(); ++i) {
    geometry_msgs::Point p = point(s.node_displacement_m[i], config.marker_scale);
    p.z = node_z_m[i] - z0;
    line.points.push_back(p);
    nodes.points.push_back(p);
    std_msgs::ColorRGBA c = nodes.color;
    if (static_cast<int>(i) == station_node) c.g = c.b = 0.1f;
    nodes.colors.push_back(c);
  }
  for (Marker& m : array.markers) {
    m.ns = "shaft";
    m.header.stamp = stamp;
  }
  return array;
}

}  // namespace rotor_rub::ros_node
