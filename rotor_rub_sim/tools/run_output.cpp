#include "run_output.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <nlohmann/json.hpp>

#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/solver_registry.hpp"
#include "rotor_rub_sim/core/trajectory_compare.hpp"

namespace rotor_rub::tools {
void RunRecorder::on_sample(const core::Sample& s) {
  if (keep_samples_) samples.push_back(s);
  last_sample = s;
  max_orbit_m = std::max(max_orbit_m, s.kin.rotor_pos.norm());
  max_normal_force_N = std::max(max_normal_force_N, s.normal_force_N);
  max_penetration_m = std::max(max_penetration_m, s.penetration_m);
}

void write_csv(std::ostream& os, const std::vector<core::Sample>& samples) {
  os << "t,x_r,y_r,x_s,y_s,vx_r,vy_r,vx_s,vy_s,normal_force,friction_force,fx_contact,fy_contact,"
        "penetration,sliding_velocity,in_contact,spin_angle,speed,sticking,drive_torque,friction_torque\n";
  char buf[1024];
  for (const auto& s : samples) {
    std::snprintf(buf, sizeof buf,
                  "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%.17g,%"
                  ".17g,%d,%.17g,%.17g\n",
                  s.t_s, s.kin.rotor_pos.x(), s.kin.rotor_pos.y(), s.kin.stator_pos.x(), s.kin.stator_pos.y(),
                  s.kin.rotor_vel.x(), s.kin.rotor_vel.y(), s.kin.stator_vel.x(), s.kin.stator_vel.y(),
                  s.normal_force_N, s.friction_force_N, s.contact_force_on_rotor_N.x(), s.contact_force_on_rotor_N.y(),
                  s.penetration_m, s.sliding_velocity_m_per_s, s.in_contact ? 1 : 0, s.drive.angle_rad,
                  s.drive.speed_rad_per_s, s.sticking ? 1 : 0, s.drive_torque_N_m, s.friction_torque_N_m);
    os << buf;
  }
}

void write_keyphasor_csv(std::ostream& os, const std::vector<core::Sample>& marks) {
  os << "t,revolution,speed\n";
  char buf[128];
  for (std::size_t k = 0; k < marks.size(); ++k) {
    std::snprintf(buf, sizeof buf, "%.17g,%zu,%.17g\n", marks[k].t_s, k + 1, marks[k].drive.speed_rad_per_s);
    os << buf;
  }
}

void write_probes_csv(std::ostream& os, const std::vector<core::ProbeReading>& readings) {
  os << "t,x_V,y_V,x_m,y_m\n";
  char buf[160];
  for (const auto& r : readings) {
    std::snprintf(buf, sizeof buf, "%.17g,%.17g,%.17g,%.17g,%.17g\n", r.t_s, r.x_V, r.y_V, r.x_m, r.y_m);
    os << buf;
  }
}

void write_shaft_csv(std::ostream& os, const std::vector<core::ShaftSample>& shaft,
                     const std::vector<double>& node_z_m) {
  os << "t,node,z_m,x_m,y_m\n";
  char buf[160];
  for (const auto& s : shaft) {
    for (std::size_t i = 0; i < s.node_displacement_m.size() && i < node_z_m.size(); ++i) {
      std::snprintf(buf, sizeof buf, "%.17g,%zu,%.17g,%.17g,%.17g\n", s.t_s, i, node_z_m[i],
                    s.node_displacement_m[i].x(), s.node_displacement_m[i].y());
      os << buf;
    }
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
  // ordered_json keeps the keys in the order people read them; a NaN (a
  // figure the run does not have, e.g. no contact) is written as null.
  using Json = nlohmann::ordered_json;
  const core::Scene& sc = *in.scene;
  const core::RunStats& st = in.stats;
  Json j;
  j["scene"] = in.scene_path;
  j["method"] = core::to_string(sc.solver.method);
  j["integrator"] = core::to_string(core::effective_integrator(sc));
  j["rtol"] = sc.solver.rtol;
  j["atol"] = sc.solver.atol;
  // Every key of the scene that ran (defaults, file and overrides), as text
  // that reads back to the same scene: the run can be repeated from this.
  j["scene_values"] = core::scene_values(sc);
  // What the contact meets (a flexible rotor's station mass is the reduced
  // model's, not in the scene), and the penalty spring's mode on it.
  const auto& cp = in.contact_point;
  j["contact_point"] = {{"mass_kg", cp.mass_kg},
                        {"effective_mass_kg", cp.effective_mass_kg},
                        {"contact_mode_hz", cp.contact_mode_rad_per_s / (2.0 * M_PI)},
                        {"contact_damping_N_s_per_m", cp.contact_damping_N_s_per_m}};
  // A flexible rotor's reduction: its planar modes (auto's choice where asked)
  // and the unbalance response's truncation error judged at the start.
  if (in.reduction.planar_modes > 0) {
    const core::TruncationReport& t = in.reduction.truncation;
    Json r = {{"planar_modes", in.reduction.planar_modes}, {"auto", t.chosen}};
    if (t.chosen) r["truncation_tolerance"] = t.tolerance;
    r["response_error"] = std::isnan(t.response_error) ? Json(nullptr) : Json(t.response_error);
    r["judged_speeds_rad_per_s"] = {t.min_speed_rad_per_s, t.max_speed_rad_per_s};
    r["judged_critical_speeds_rad_per_s"] = t.critical_speeds_rad_per_s;
    j["rotor_reduction"] = r;
  } else {
    j["rotor_reduction"] = nullptr;
  }
  if (*in.failure) {
    j["status"] = core::to_string((*in.failure)->failure_class);
    j["failure"] = {{"t", (*in.failure)->time_s}, {"message", (*in.failure)->message}};
  } else {
    j["status"] = "ok";
  }
  const auto& events = in.recorder->events;
  const auto sustained = core::longest_contact(events, in.end_time_s);
  j["first_contact_s"] = core::first_contact_s(events);
  j["first_touchdown_s"] = first_touchdown_s(events);
  j["sustained_contact_s"] = {sustained.first, sustained.second};
  j["last_liftoff_s"] = last_liftoff_s(events);
  j["last_contact_end_s"] = core::last_contact_end_s(events);
  j["max_orbit_m"] = in.recorder->max_orbit_m;
  j["max_normal_force_N"] = in.recorder->max_normal_force_N;
  j["max_penetration_m"] = in.recorder->max_penetration_m;
  j["events"] = Json::array();
  for (const auto& e : events) {
    j["events"].push_back({{"t", e.t_s},
                           {"kind", core::to_string(e.kind)},
                           {"normal_velocity_m_per_s", e.normal_velocity_m_per_s},
                           {"impulse_N_s", e.impulse_N_s}});
  }
  j["stats"] = {{"steps", st.steps},
                {"rejected_steps", st.rejected_steps},
                {"rhs_evals", st.rhs_evals},
                {"jacobian_evals", st.jacobian_evals},
                {"root_iterations", st.root_iterations},
                {"touchdowns", st.touchdowns},
                {"liftoffs", st.liftoffs},
                {"grazes", st.grazes},
                {"restarts", st.restarts},
                {"friction_transitions", st.friction_transitions},
                {"integrator_switches", st.integrator_switches},
                {"wall_time_s", st.wall_time_s},
                {"max_constraint_violation_m", st.max_constraint_violation_m},
                {"min_abs_sliding_velocity_m_per_s",
                 st.min_abs_sliding_velocity_m_per_s > 1e299 ? std::nan("") : st.min_abs_sliding_velocity_m_per_s}};
  // Bytes that are not UTF-8 (a scene path in another encoding) are replaced,
  // not a throw after the run.
  os << j.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << "\n";
}

}  // namespace rotor_rub::tools
