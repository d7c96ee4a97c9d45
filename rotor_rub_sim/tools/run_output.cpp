#include "run_output.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

#include "rotor_rub_sim/core/trajectory_compare.hpp"

namespace rotor_rub::tools {
namespace {

std::string num(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += (c == '\n') ? ' ' : c;
  }
  return out;
}

}  // namespace

void RunRecorder::on_sample(const core::Sample& s) {
  if (keep_samples_) samples.push_back(s);
  last_sample = s;
  max_orbit_m = std::max(max_orbit_m, s.kin.rotor_pos.norm());
  max_normal_force_N = std::max(max_normal_force_N, s.normal_force_N);
  max_penetration_m = std::max(max_penetration_m, s.penetration_m);
}

void write_csv(std::ostream& os, const std::vector<core::Sample>& samples) {
  os << "t,x_r,y_r,x_s,y_s,vx_r,vy_r,vx_s,vy_s,normal_force,friction_force,fx_contact,fy_contact,"
        "penetration,sliding_velocity,in_contact,spin_angle,speed,sticking\n";
  char buf[1024];
  for (const auto& s : samples) {
    std::snprintf(
        buf, sizeof buf,
        "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%.17g,%d\n",
        s.t_s, s.kin.rotor_pos.x(), s.kin.rotor_pos.y(), s.kin.stator_pos.x(), s.kin.stator_pos.y(),
        s.kin.rotor_vel.x(), s.kin.rotor_vel.y(), s.kin.stator_vel.x(), s.kin.stator_vel.y(), s.normal_force_N,
        s.friction_force_N, s.contact_force_on_rotor_N.x(), s.contact_force_on_rotor_N.y(), s.penetration_m,
        s.sliding_velocity_m_per_s, s.in_contact ? 1 : 0, s.drive.angle_rad, s.drive.speed_rad_per_s,
        s.sticking ? 1 : 0);
    os << buf;
  }
}

double first_touchdown_s(const std::vector<core::ContactEvent>& events) {
  for (const auto& e : events) {
    if (e.kind == core::EventKind::kTouchdown) return e.t_s;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double last_liftoff_s(const std::vector<core::ContactEvent>& events) {
  for (auto it = events.rbegin(); it != events.rend(); ++it) {
    if (it->kind == core::EventKind::kLiftoff) return it->t_s;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

void write_summary_json(std::ostream& os, const SummaryInput& in) {
  const core::Scene& sc = *in.scene;
  const core::RunStats& st = in.stats;
  os << "{\n  \"scene\": \"" << in.scene_path << "\",\n";
  os << "  \"method\": \"" << core::to_string(sc.solver.method) << "\",\n";
  os << "  \"integrator\": \"" << core::to_string(sc.solver.integrator) << "\",\n";
  os << "  \"rtol\": " << num(sc.solver.rtol) << ",\n  \"atol\": " << num(sc.solver.atol) << ",\n";
  if (*in.failure) {
    os << "  \"status\": \"" << core::to_string((*in.failure)->failure_class) << "\",\n";
    os << "  \"failure\": {\"t\": " << num((*in.failure)->time_s) << ", \"message\": \""
       << json_escape((*in.failure)->message) << "\"},\n";
  } else {
    os << "  \"status\": \"ok\",\n";
  }
  const auto sustained = core::longest_contact(in.recorder->events);
  os << "  \"first_contact_s\": " << num(core::first_contact_s(in.recorder->events)) << ",\n";
  os << "  \"first_touchdown_s\": " << num(first_touchdown_s(in.recorder->events)) << ",\n";
  os << "  \"sustained_contact_s\": [" << num(sustained.first) << ", " << num(sustained.second) << "],\n";
  os << "  \"last_liftoff_s\": " << num(last_liftoff_s(in.recorder->events)) << ",\n";
  os << "  \"last_contact_end_s\": " << num(core::last_contact_end_s(in.recorder->events)) << ",\n";
  os << "  \"max_orbit_m\": " << num(in.recorder->max_orbit_m) << ",\n";
  os << "  \"max_normal_force_N\": " << num(in.recorder->max_normal_force_N) << ",\n";
  os << "  \"max_penetration_m\": " << num(in.recorder->max_penetration_m) << ",\n";
  os << "  \"events\": [";
  for (std::size_t i = 0; i < in.recorder->events.size(); ++i) {
    const auto& e = in.recorder->events[i];
    os << (i ? ",\n    " : "\n    ") << "{\"t\": " << num(e.t_s) << ", \"kind\": \"" << core::to_string(e.kind)
       << "\", \"normal_velocity_m_per_s\": " << num(e.normal_velocity_m_per_s)
       << ", \"impulse_N_s\": " << num(e.impulse_N_s) << "}";
  }
  os << (in.recorder->events.empty() ? "],\n" : "\n  ],\n");
  os << "  \"stats\": {\"steps\": " << st.steps << ", \"rejected_steps\": " << st.rejected_steps
     << ", \"rhs_evals\": " << st.rhs_evals << ", \"jacobian_evals\": " << st.jacobian_evals
     << ", \"root_iterations\": " << st.root_iterations << ", \"touchdowns\": " << st.touchdowns
     << ", \"liftoffs\": " << st.liftoffs << ", \"grazes\": " << st.grazes << ", \"restarts\": " << st.restarts
     << ", \"friction_transitions\": " << st.friction_transitions << ", \"wall_time_s\": " << num(st.wall_time_s)
     << ", \"max_constraint_violation_m\": " << num(st.max_constraint_violation_m)
     << ", \"min_abs_sliding_velocity_m_per_s\": "
     << num(st.min_abs_sliding_velocity_m_per_s > 1e299 ? std::nan("") : st.min_abs_sliding_velocity_m_per_s)
     << "}\n}\n";
}

}  // namespace rotor_rub::tools
