#include "run_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "rotor_rub_sim/core/trajectory_compare.hpp"

namespace rotor_rub::tools {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Two samples are at the same time when their stamps agree to 1 ns: bags
// store stamps in nanoseconds, the runner's CSV in full double precision.
constexpr double kSameTime_s = 1e-9;

std::string num(double v) {
  if (std::isnan(v)) return "nan";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

// The summary writes a figure the run does not have (NaN) as null.
double number_or_nan(const nlohmann::json& v) { return v.is_null() ? kNaN : v.get<double>(); }

}  // namespace

RunFigures compare_run(const RecordedRun& run, const RecordedRun& ref) {
  RunFigures f;
  f.name = run.name;
  f.method = run.method;
  f.integrator = run.integrator;
  f.samples = run.samples.size();
  f.lost_samples = run.lost_samples;
  f.first_contact_s = run.has_events ? core::first_contact_s(run.events) : kNaN;
  f.last_contact_end_s = run.has_events ? core::last_contact_end_s(run.events) : kNaN;
  f.first_touchdown_s = f.last_liftoff_s = kNaN;
  for (const auto& e : run.events) {
    if (e.kind == core::EventKind::kTouchdown) {
      ++f.touchdowns;
      if (std::isnan(f.first_touchdown_s)) f.first_touchdown_s = e.t_s;
    } else if (e.kind == core::EventKind::kLiftoff) {
      ++f.liftoffs;
      f.last_liftoff_s = e.t_s;
    } else {
      ++f.grazes;
    }
  }
  double force_sum = 0.0;
  long in_contact = 0;
  for (const auto& s : run.samples) {
    f.max_orbit_m = std::max(f.max_orbit_m, s.kin.rotor_pos.norm());
    f.max_normal_force_N = std::max(f.max_normal_force_N, s.normal_force_N);
    if (s.in_contact) {
      ++in_contact;
      force_sum += s.normal_force_N;
    }
  }
  f.mean_normal_force_in_contact_N = in_contact ? force_sum / static_cast<double>(in_contact) : kNaN;
  f.first_change_s = run.changes.empty() ? kNaN : run.changes.front().t_s;
  f.first_contact_after_change_s = kNaN;
  for (const auto& e : run.events) {
    if (!run.changes.empty() && e.kind != core::EventKind::kLiftoff && e.t_s >= f.first_change_s) {
      f.first_contact_after_change_s = e.t_s;
      break;
    }
  }
  for (const LiveChange& c : run.changes) {
    char t[64];
    if (c.steps <= 1) {
      std::snprintf(t, sizeof t, "%.9g", c.t_s);
      f.changes += (f.changes.empty() ? "" : "; ") + std::string(t) + " " + c.what;
    } else {  // a ramp: one change to a user
      std::snprintf(t, sizeof t, "%.9g..%.9g", c.t_s, c.end_s);
      f.changes += (f.changes.empty() ? "" : "; ") + std::string(t) + " " + c.what + " " + c.from + ".." + c.values +
                   " (" + std::to_string(c.steps) + " steps)";
    }
    ++f.live_changes;
  }
  if (run.samples.size() >= 2) {
    const double period = (run.samples.back().t_s - run.samples.front().t_s) / double(run.samples.size() - 1);
    f.contact_time_s = static_cast<double>(in_contact) * period;
  }
  // Differences on the common sample times (a merge of two sorted grids).
  double rotor2 = 0.0, stator2 = 0.0;
  f.max_rotor_diff_m = f.max_stator_diff_m = f.max_normal_force_diff_N = 0.0;
  std::size_t i = 0, j = 0;
  while (i < run.samples.size() && j < ref.samples.size()) {
    const double ti = run.samples[i].t_s, tj = ref.samples[j].t_s;
    if (ti < tj - kSameTime_s) {
      ++i;
    } else if (tj < ti - kSameTime_s) {
      ++j;
    } else {
      const auto& a = run.samples[i];
      const auto& b = ref.samples[j];
      const double dr = (a.kin.rotor_pos - b.kin.rotor_pos).norm();
      const double ds = (a.kin.stator_pos - b.kin.stator_pos).norm();
      f.max_rotor_diff_m = std::max(f.max_rotor_diff_m, dr);
      f.max_stator_diff_m = std::max(f.max_stator_diff_m, ds);
      f.max_normal_force_diff_N = std::max(f.max_normal_force_diff_N, std::abs(a.normal_force_N - b.normal_force_N));
      rotor2 += dr * dr;
      stator2 += ds * ds;
      ++f.common_samples;
      ++i;
      ++j;
    }
  }
  const double n = static_cast<double>(f.common_samples);
  f.rms_rotor_diff_m = f.common_samples ? std::sqrt(rotor2 / n) : kNaN;
  f.rms_stator_diff_m = f.common_samples ? std::sqrt(stator2 / n) : kNaN;
  if (!f.common_samples) f.max_rotor_diff_m = f.max_stator_diff_m = f.max_normal_force_diff_N = kNaN;
  const bool events_both = run.has_events && ref.has_events;
  f.first_contact_diff_s = events_both ? f.first_contact_s - core::first_contact_s(ref.events) : kNaN;
  f.last_contact_end_diff_s = events_both ? f.last_contact_end_s - core::last_contact_end_s(ref.events) : kNaN;
  f.steps = run.steps;
  f.rhs_evals = run.rhs_evals;
  f.integration_wall_s = run.integration_wall_s;
  f.real_time_factor = run.real_time_factor;
  return f;
}

void print_table(std::ostream& os, const std::vector<RunFigures>& rows, const std::string& reference_name) {
  char buf[512];
  os << "reference: " << reference_name << "\n";
  std::snprintf(buf, sizeof buf, "%-44s %-9s %-11s %7s %4s %12s %12s %10s %10s %10s %10s %9s %8s %9s\n", "run",
                "method", "integrator", "samples", "lost", "1st contact", "contact end", "max |r_r|", "max F_n",
                "max|dr_r|", "rms|dr_r|", "max|dr_s|", "steps", "wall");
  os << buf;
  std::snprintf(buf, sizeof buf, "%-44s %-9s %-11s %7s %4s %12s %12s %10s %10s %10s %10s %9s %8s %9s\n", "", "", "", "",
                "", "[s]", "[s]", "[m]", "[N]", "[m]", "[m]", "[m]", "", "[s]");
  os << buf;
  // A figure the run does not carry (a bag without contact events or solver
  // stats, e.g. from `rosbag record` of the states alone) prints as "-".
  auto fixed = [](double v, const char* fmt) {
    if (std::isnan(v)) return std::string("-");
    char b[40];
    std::snprintf(b, sizeof b, fmt, v);
    return std::string(b);
  };
  bool missing = false;
  for (const auto& r : rows) {
    const std::string method = r.method.empty() ? "-" : r.method;
    const std::string integrator = r.integrator.empty() ? "-" : r.integrator;
    const std::string steps = r.steps < 0 ? "-" : std::to_string(r.steps);
    const std::string wall = r.steps < 0 ? "-" : fixed(r.integration_wall_s, "%.4f");
    missing = missing || r.steps < 0 || std::isnan(r.first_contact_s);
    std::snprintf(buf, sizeof buf, "%-44s %-9s %-11s %7zu %4ld %12s %12s %10.4g %10.4g %10.3g %10.3g %9.3g %8s %9s\n",
                  r.name.c_str(), method.c_str(), integrator.c_str(), r.samples, r.lost_samples,
                  fixed(r.first_contact_s, "%.9f").c_str(), fixed(r.last_contact_end_s, "%.9f").c_str(), r.max_orbit_m,
                  r.max_normal_force_N, r.max_rotor_diff_m, r.rms_rotor_diff_m, r.max_stator_diff_m, steps.c_str(),
                  wall.c_str());
    os << buf;
  }
  for (const auto& r : rows) {
    if (r.live_changes > 0) os << "live changes in " << r.name << " [s]: " << r.changes << "\n";
  }
  os << "max |r_r|: the rotor's absolute orbit (the stator moves too; |r_r - r_s| stays within the clearance)\n";
  if (missing) {
    os << "-: not in the run (a bag without contact events or solver stats, or a run without contact)\n";
  }
}

void write_figures_csv(std::ostream& os, const std::vector<RunFigures>& rows) {
  os << "run,method,integrator,samples,lost_samples,first_contact_s,first_touchdown_s,last_liftoff_s,last_contact_end_"
        "s,"
        "touchdowns,liftoffs,grazes,max_orbit_m,max_normal_force_N,mean_normal_force_in_contact_N,contact_time_s,"
        "common_samples,max_rotor_diff_m,rms_rotor_diff_m,max_stator_diff_m,rms_stator_diff_m,"
        "max_normal_force_diff_N,first_contact_diff_s,last_contact_end_diff_s,steps,rhs_evals,integration_wall_s,"
        "real_time_factor,live_changes,first_change_s,first_contact_after_change_s,changes\n";
  for (const auto& r : rows) {
    os << r.name << "," << r.method << "," << r.integrator << "," << r.samples << "," << r.lost_samples << ","
       << num(r.first_contact_s) << "," << num(r.first_touchdown_s) << "," << num(r.last_liftoff_s) << ","
       << num(r.last_contact_end_s) << "," << r.touchdowns << "," << r.liftoffs << "," << r.grazes << ","
       << num(r.max_orbit_m) << "," << num(r.max_normal_force_N) << "," << num(r.mean_normal_force_in_contact_N) << ","
       << num(r.contact_time_s) << "," << r.common_samples << "," << num(r.max_rotor_diff_m) << ","
       << num(r.rms_rotor_diff_m) << "," << num(r.max_stator_diff_m) << "," << num(r.rms_stator_diff_m) << ","
       << num(r.max_normal_force_diff_N) << "," << num(r.first_contact_diff_s) << "," << num(r.last_contact_end_diff_s)
       << "," << r.steps << "," << r.rhs_evals << "," << num(r.integration_wall_s) << "," << num(r.real_time_factor)
       << "," << r.live_changes << "," << num(r.first_change_s) << "," << num(r.first_contact_after_change_s) << ","
       << r.changes << "\n";
  }
}

RecordedRun read_runner_csv(const std::string& csv_path, const std::string& summary_path) {
  std::ifstream in(csv_path);
  if (!in) throw std::runtime_error("cannot read the runner CSV '" + csv_path + "'");
  RecordedRun run;
  run.name = csv_path.substr(csv_path.find_last_of('/') + 1);
  std::string line;
  if (!std::getline(in, line) || line.rfind("t,x_r,y_r,x_s,y_s,", 0) != 0) {
    throw std::runtime_error("'" + csv_path + "' is not a rotor_rub_run CSV (header t,x_r,y_r,x_s,y_s,...)");
  }
  long row = 1;
  while (std::getline(in, line)) {
    ++row;
    std::vector<double> v;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) v.push_back(std::strtod(cell.c_str(), nullptr));
    if (v.size() < 18) throw std::runtime_error("'" + csv_path + "' row " + std::to_string(row) + " is truncated");
    core::Sample s;
    s.t_s = v[0];
    s.kin.rotor_pos = {v[1], v[2]};
    s.kin.stator_pos = {v[3], v[4]};
    s.kin.rotor_vel = {v[5], v[6]};
    s.kin.stator_vel = {v[7], v[8]};
    s.normal_force_N = v[9];
    s.friction_force_N = v[10];
    s.contact_force_on_rotor_N = {v[11], v[12]};
    s.penetration_m = v[13];
    s.sliding_velocity_m_per_s = v[14];
    s.in_contact = v[15] != 0.0;
    s.drive.angle_rad = v[16];
    s.drive.speed_rad_per_s = v[17];
    if (v.size() >= 21) {  // drive_torque, friction_torque (CSVs written before them lack both)
      s.drive_torque_N_m = v[19];
      s.friction_torque_N_m = v[20];
    }
    run.samples.push_back(s);
  }
  std::ifstream js(summary_path);
  if (js) {
    // The runner's summary (run_output.cpp writes it with the same library).
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(js);
      run.method = j.at("method").get<std::string>();
      run.integrator = j.value("integrator", std::string());
      const auto& stats = j.at("stats");
      run.steps = stats.at("steps").get<long>();
      run.rhs_evals = stats.at("rhs_evals").get<long>();
      run.integration_wall_s = number_or_nan(stats.at("wall_time_s"));
      for (const auto& e : j.at("events")) {
        core::ContactEvent ev;
        ev.t_s = number_or_nan(e.at("t"));
        ev.kind = core::value_named(core::kAllEventKinds, e.at("kind").get<std::string>(), "event kind");
        ev.normal_velocity_m_per_s = number_or_nan(e.at("normal_velocity_m_per_s"));
        ev.impulse_N_s = number_or_nan(e.at("impulse_N_s"));
        run.events.push_back(ev);
      }
    } catch (const std::exception& e) {
      throw std::runtime_error("'" + summary_path + "' is not a rotor_rub_run summary: " + e.what());
    }
    run.has_events = true;
  }
  return run;
}

}  // namespace rotor_rub::tools
