#include "sweep_csv.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <stdexcept>

#include "rotor_rub_sim/core/solver_registry.hpp"

namespace rotor_rub::tools {
namespace {

// Full precision: shards and reruns must reproduce the same bytes.
std::string num(double v) {
  if (std::isnan(v)) return "nan";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Settings read back as the values the user wrote (0.1, not 0.10000000000000001).
std::string setting(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += (c == '\n') ? ' ' : c;
  }
  return out + "\"";
}

// The grid values that have no column of their own, as "k=v;k=v".
const char* const kOwnColumns[] = {
    "method",      "integrator",           "rtol",          "atol", "contact_stiffness_N_per_m",
    "restitution", "friction_coefficient", "eccentricity_m"};

std::string other_overrides(const Values& v) {
  std::string out;
  for (const auto& [k, val] : v) {
    bool own = false;
    for (const char* c : kOwnColumns) own = own || k == c;
    if (own) continue;
    if (!out.empty()) out += ';';
    out += k + "=" + val;
  }
  return out;
}

}  // namespace

std::string sweep_csv_header() {
  return "run_id,runs_total,method,integrator,rtol,atol,contact_stiffness_N_per_m,restitution,friction_coefficient,"
         "eccentricity_m,other_settings,status,failure_time_s,message,wall_time_s,repeats,steps,rejected_steps,"
         "rhs_evals,jacobian_evals,root_iterations,touchdowns,liftoffs,grazes,rhs_share,iteration_share,"
         "compared_samples,max_rotor_err_m,rms_rotor_err_m,max_stator_err_m,rms_stator_err_m,first_contact_s,"
         "first_contact_err_s,last_contact_end_s,last_contact_end_err_s,impulse_window_err_rel,"
         "impulse_windows_within_5pct,ref_peak_window_force_N,max_orbit_m,peak_normal_force_N,contact_time_s,stick_"
         "time_s,horizon_s,max_rotor_err_in_horizon_m,max_event_err_s,event_mismatch_s";
}

void write_sweep_row(std::ostream& os, const SweepResult& r) {
  const auto& s = r.scene;
  const bool valid = r.status != "invalid";
  // An invalid run shows the grid's text for the columns it set.
  auto col = [&](const char* key, const std::string& effective) {
    const auto it = r.overrides.find(key);
    return valid ? effective : (it == r.overrides.end() ? std::string() : it->second);
  };
  const auto& st = r.stats;
  const auto& e = r.errors;
  os << r.id << ',' << r.runs_total << ',' << col("method", core::to_string(s.solver.method)) << ','
     << col("integrator", core::to_string(core::effective_integrator(s))) << ',' << col("rtol", setting(s.solver.rtol))
     << ',' << col("atol", setting(s.solver.atol)) << ','
     << col("contact_stiffness_N_per_m", setting(s.model.contact_stiffness_N_per_m)) << ','
     << col("restitution", setting(s.model.restitution)) << ','
     << col("friction_coefficient", setting(s.model.friction_coefficient)) << ','
     << col("eccentricity_m", setting(s.model.eccentricity_m)) << ',' << quoted(other_overrides(r.overrides)) << ','
     << r.status << ',' << num(r.failure_time_s) << ',' << quoted(r.message) << ',' << num(r.wall_time_s) << ','
     << r.repeats << ',' << st.steps << ',' << st.rejected_steps << ',' << st.rhs_evals << ',' << st.jacobian_evals
     << ',' << st.root_iterations << ',' << st.touchdowns << ',' << st.liftoffs << ',' << st.grazes << ','
     << num(r.rhs_share) << ',' << num(r.iteration_share) << ',' << e.samples << ',' << num(e.max_rotor_m) << ','
     << num(e.rms_rotor_m) << ',' << num(e.max_stator_m) << ',' << num(e.rms_stator_m) << ',' << num(e.first_contact_s)
     << ',' << num(e.first_contact_err_s) << ',' << num(e.last_contact_end_s) << ',' << num(e.last_contact_end_err_s)
     << ',' << num(e.impulse_window_err_rel) << ',' << num(e.impulse_windows_within_5pct) << ','
     << num(e.ref_peak_window_force_N) << ',' << num(e.max_orbit_m) << ',' << num(e.peak_normal_force_N) << ','
     << num(e.contact_time_s) << ',' << num(e.stick_time_s) << ',' << num(r.horizon_s) << ','
     << num(e.max_rotor_in_horizon_m) << ',' << num(e.max_event_err_s) << ',' << num(e.event_mismatch_s) << '\n';
}

void merge_sweep_csvs(const std::vector<std::string>& parts, std::ostream& out) {
  const std::string header = sweep_csv_header();
  std::map<std::size_t, std::string> rows;
  std::size_t total = 0;
  bool have_total = false;
  for (const auto& path : parts) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read shard '" + path + "'");
    std::string line;
    if (!std::getline(in, line) || line != header) {
      throw std::runtime_error("shard '" + path + "' is not a sweep CSV of this version (header differs)");
    }
    while (std::getline(in, line)) {
      if (line.empty()) continue;
      std::size_t pos = 0;
      const std::size_t id = std::stoul(line, &pos);
      const std::size_t n = std::stoul(line.substr(pos + 1));
      if (have_total && n != total) throw std::runtime_error("shard '" + path + "' is from a different grid");
      total = n;
      have_total = true;
      if (!rows.emplace(id, line).second) {
        throw std::runtime_error("run " + std::to_string(id) + " appears twice (shard '" + path + "')");
      }
    }
  }
  if (rows.size() != total) {
    std::string missing;
    for (std::size_t i = 0; i < total && missing.size() < 200; ++i) {
      if (!rows.count(i)) missing += " " + std::to_string(i);
    }
    throw std::runtime_error("merge: " + std::to_string(total - rows.size()) + " of " + std::to_string(total) +
                             " runs missing:" + missing);
  }
  out << header << '\n';
  for (const auto& [id, line] : rows) out << line << '\n';
}

}  // namespace rotor_rub::tools
