#include "rotor_rub_sim/ros/conversions.hpp"

#include <ros/param.h>

#include <cstdio>

#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/solver_registry.hpp"

namespace rotor_rub::ros_node {
namespace {

// The model's plane is x-y: z is always 0.
template <class Xyz>
void set_xy(const core::Vec2& v, Xyz& out) {
  out.x = v.x();
  out.y = v.y();
  out.z = 0.0;
}

}  // namespace

void to_msg(const core::Sample& s, uint64_t sample_index, const std::string& frame_id,
            rotor_rub_msgs::RotorState& msg) {
  msg.sample_index = sample_index;
  msg.header.stamp.fromSec(s.t_s);
  msg.header.frame_id = frame_id;
  set_xy(s.kin.rotor_pos, msg.rotor_position);
  set_xy(s.kin.rotor_vel, msg.rotor_velocity);
  set_xy(s.kin.stator_pos, msg.stator_position);
  set_xy(s.kin.stator_vel, msg.stator_velocity);
  msg.normal_force = s.normal_force_N;
  msg.friction_force = s.friction_force_N;
  set_xy(s.contact_force_on_rotor_N, msg.contact_force);
  msg.in_contact = s.in_contact;
  msg.penetration = s.penetration_m;
  msg.sliding_velocity = s.sliding_velocity_m_per_s;
  msg.spin_angle = s.drive.angle_rad;
  msg.speed = s.drive.speed_rad_per_s;
  msg.angular_acceleration = s.drive.accel_rad_per_s2;
  msg.drive_torque = s.drive_torque_N_m;
  msg.friction_torque = s.friction_torque_N_m;
}

void to_msg(const core::ContactEvent& e, const std::string& frame_id, rotor_rub_msgs::ContactEvent& msg) {
  msg.header.stamp.fromSec(e.t_s);
  msg.header.frame_id = frame_id;
  msg.time = e.t_s;
  switch (e.kind) {
    case core::EventKind::kTouchdown:
      msg.kind = rotor_rub_msgs::ContactEvent::TOUCHDOWN;
      break;
    case core::EventKind::kLiftoff:
      msg.kind = rotor_rub_msgs::ContactEvent::LIFTOFF;
      break;
    case core::EventKind::kGraze:
      msg.kind = rotor_rub_msgs::ContactEvent::GRAZE;
      break;
  }
  msg.kind_name = core::to_string(e.kind);
  msg.normal_velocity = e.normal_velocity_m_per_s;
  msg.impulse = e.impulse_N_s;
}

void to_msg(const core::RunStats& st, const core::Scene& scene, rotor_rub_msgs::SolverStats& msg) {
  msg.method = core::to_string(scene.solver.method);
  msg.integrator = core::to_string(core::effective_integrator(scene));
  msg.steps = st.steps;
  msg.rejected_steps = st.rejected_steps;
  msg.rhs_evaluations = st.rhs_evals;
  msg.jacobian_evaluations = st.jacobian_evals;
  msg.root_iterations = st.root_iterations;
  msg.touchdowns = st.touchdowns;
  msg.liftoffs = st.liftoffs;
  msg.grazes = st.grazes;
  msg.restarts = st.restarts;
  msg.integration_wall_time = st.wall_time_s;
}

core::Sample from_msg(const rotor_rub_msgs::RotorState& msg) {
  core::Sample s;
  s.t_s = msg.header.stamp.toSec();
  s.kin.rotor_pos = core::Vec2(msg.rotor_position.x, msg.rotor_position.y);
  s.probe_displacement_m = s.kin.rotor_pos;  // the state topic holds the rotor (a flexible rotor's station)
  s.kin.rotor_vel = core::Vec2(msg.rotor_velocity.x, msg.rotor_velocity.y);
  s.kin.stator_pos = core::Vec2(msg.stator_position.x, msg.stator_position.y);
  s.kin.stator_vel = core::Vec2(msg.stator_velocity.x, msg.stator_velocity.y);
  s.normal_force_N = msg.normal_force;
  s.friction_force_N = msg.friction_force;
  s.contact_force_on_rotor_N = core::Vec2(msg.contact_force.x, msg.contact_force.y);
  s.in_contact = msg.in_contact;
  s.penetration_m = msg.penetration;
  s.sliding_velocity_m_per_s = msg.sliding_velocity;
  s.drive.angle_rad = msg.spin_angle;
  s.drive.speed_rad_per_s = msg.speed;
  s.drive.accel_rad_per_s2 = msg.angular_acceleration;
  s.drive_torque_N_m = msg.drive_torque;
  s.friction_torque_N_m = msg.friction_torque;
  return s;
}

core::ContactEvent from_msg(const rotor_rub_msgs::ContactEvent& msg) {
  core::ContactEvent e;
  e.t_s = msg.time;
  e.kind = msg.kind == rotor_rub_msgs::ContactEvent::TOUCHDOWN ? core::EventKind::kTouchdown
           : msg.kind == rotor_rub_msgs::ContactEvent::LIFTOFF ? core::EventKind::kLiftoff
                                                               : core::EventKind::kGraze;
  e.normal_velocity_m_per_s = msg.normal_velocity;
  e.impulse_N_s = msg.impulse;
  return e;
}

std::map<std::string, std::string> private_params_as_text(const ros::NodeHandle& private_nh) {
  std::vector<std::string> names;
  ros::param::getParamNames(names);
  const std::string prefix = private_nh.getNamespace() + "/";
  std::map<std::string, std::string> values;
  for (const auto& name : names) {
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string key = name.substr(prefix.size());
    // diagnostic_updater reads its own ~diagnostic_period.
    if (key == "diagnostic_period") continue;
    XmlRpc::XmlRpcValue v;
    if (!private_nh.getParam(key, v)) continue;
    switch (v.getType()) {
      case XmlRpc::XmlRpcValue::TypeDouble: {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.17g", static_cast<double>(v));
        values[key] = buf;
        break;
      }
      case XmlRpc::XmlRpcValue::TypeInt:
        values[key] = std::to_string(static_cast<int>(v));
        break;
      case XmlRpc::XmlRpcValue::TypeBoolean:
        values[key] = static_cast<bool>(v) ? "true" : "false";
        break;
      case XmlRpc::XmlRpcValue::TypeString:
        values[key] = static_cast<std::string>(v);
        break;
      default:
        throw core::SceneError("parameter '" + key +
                               "' has a type no key accepts (a list, a dictionary or binary); accepted: a number, "
                               "a boolean or a name, as config/scene_template.yaml lists");
    }
  }
  return values;
}

}  // namespace rotor_rub::ros_node
