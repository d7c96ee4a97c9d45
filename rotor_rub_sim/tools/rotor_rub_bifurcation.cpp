// rotor_rub_bifurcation: what the rotor does at each speed once the
// transient has died, and whether it depends on the way there. ROS-free, on
// the core and the sweep's grid and shards (so it runs on Slurm through
// scripts/slurm_sweep.sh like the sweep).
//
// For every point of the parameter grid (--grid/--set, e.g. the friction
// coefficient) it makes
//  * "constant" runs: one per speed of --speed-from..--speed-to (--speeds of
//    them), each held from rest for --settle-s and then for --revolutions
//    revolutions, the keyphasor's Poincare points and the samples of those
//    revolutions classified (core/response_class.hpp);
//  * an "up" ramp: held at --speed-from for --settle-s, then at
//    --ramp-accel to --speed-to; and a "down" ramp the other way. Each ramp
//    is classified in speed bins centred on the grid's speeds (the
//    quasi-static diagram: the jump and hysteresis of rub show as the two
//    directions disagree).
// Output: OUT.csv, one row per classified (run, speed); OUT.csv.points.csv, every
// Poincare point (rotor minus stator at each keyphasor, after settling).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "cli_options.hpp"
#include "package_paths.hpp"
#include "rotor_rub_sim/core/response_class.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/solver_registry.hpp"
#include "sweep_grid.hpp"

namespace {

using namespace rotor_rub;
namespace cli = rotor_rub::cli;
using tools::Values;

enum class Direction { kConstant, kUp, kDown };
const char* to_string(Direction d) {
  return d == Direction::kConstant ? "constant" : d == Direction::kUp ? "up" : "down";
}

struct Options {
  std::string scene_path, grid_path, out_path;
  std::vector<tools::GridAxis> axes;
  double speed_from = 10.0, speed_to = 800.0;  // rad/s
  int speeds = 200;
  double settle_s = 10.0;
  int revolutions = 512;
  double ramp_accel = 2.0;  // rad/s^2
  bool constant = true, up = true, down = true;
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
  std::size_t shard_index = 0, shard_count = 1;
  int points_per_bin = 0;  // 0: every Poincare point
  bool count_runs = false;
  std::vector<std::string> merge;
};

struct Run {
  std::size_t id = 0;
  Values overrides;  // the parameter point's
  Direction direction = Direction::kConstant;
  double speed = 0.0;  // constant runs
};

struct Row {
  std::size_t run_id = 0, runs_total = 0;
  Direction direction = Direction::kConstant;
  double friction = 0.0, speed = 0.0;
  std::string overrides;
  std::string solver;  // what ran, auto resolved: "switching on dop853" (the summary line's)
  std::string status = "ok", message;
  core::ResponseClassification c;
  double max_relative_m = 0.0, min_relative_m = 0.0;
  std::size_t points = 0;
};

std::string overrides_text(const Values& v) {
  std::string s;
  for (const auto& [k, x] : v) s += (s.empty() ? "" : ";") + k + "=" + x;
  return s;
}

std::string num(double v) {
  if (std::isnan(v)) return "";
  char b[40];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

const char* kRowHeader =
    "run_id,runs_total,direction,friction_coefficient,speed_rad_per_s,class,contact,motion,period,k01,"
    "distinct_points,whirl,contact_fraction,mean_normal_force_N,max_relative_m,min_relative_m,points,status,"
    "message,overrides";
const char* kPointHeader =
    "run_id,direction,friction_coefficient,t_s,speed_rad_per_s,x_rel_m,y_rel_m,r_rel_m,in_contact,normal_force_N";

std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return q + "\"";
}

void write_row(std::ostream& os, const Row& r) {
  const bool classified = r.status == "ok" || r.c.motion != core::Motion::kTooShort || r.points > 0;
  os << r.run_id << ',' << r.runs_total << ',' << to_string(r.direction) << ',' << num(r.friction) << ','
     << num(r.speed) << ',' << (classified ? core::to_string(r.c.response) : "") << ','
     << (classified ? core::to_string(r.c.contact) : "") << ',' << (classified ? core::to_string(r.c.motion) : "")
     << ',' << r.c.period << ',' << num(r.c.k01) << ',' << r.c.distinct_points << ','
     << (classified ? core::to_string(r.c.whirl) : "") << ',' << num(r.c.contact_fraction) << ','
     << num(r.c.mean_normal_force_N) << ',' << num(r.max_relative_m) << ',' << num(r.min_relative_m) << ',' << r.points
     << ',' << r.status << ',' << quoted(r.message) << ',' << quoted(r.overrides) << '\n';
}

// Collects samples and Poincare points after the settling time into speed
// bins (one bin for a constant run).
class BinnedRecorder : public core::SimulationObserver {
 public:
  BinnedRecorder(double settle_s, std::vector<double> bin_edges, const core::Simulation& sim)
      : settle_s_(settle_s), edges_(std::move(bin_edges)), sim_(sim) {
    windows.resize(edges_.size() - 1);
    for (auto& w : windows) w.drifting = edges_.size() > 2;  // a ramp's bins
  }
  bool wants_keyphasor() const override { return true; }
  void on_sample(const core::Sample& s) override {
    if (auto* w = window_at(s)) w->add_sample(s);
  }
  void on_event(const core::ContactEvent& e) override {
    if (e.t_s < settle_s_) return;
    const int b = bin_of(sim_.profile().at(e.t_s).speed_rad_per_s);  // the speed at the event itself
    if (b >= 0) ++windows[static_cast<std::size_t>(b)].contact_events;
  }
  void on_keyphasor(const core::Sample& s) override {
    if (auto* w = window_at(s)) w->add_point(s);
  }
  std::vector<core::ResponseWindow> windows;

 private:
  int bin_of(double speed) const {
    for (std::size_t i = 0; i + 1 < edges_.size(); ++i) {
      if (speed >= edges_[i] && speed < edges_[i + 1]) return static_cast<int>(i);
    }
    return -1;
  }
  core::ResponseWindow* window_at(const core::Sample& s) {
    if (s.t_s < settle_s_) return nullptr;
    const int b = bin_of(s.drive.speed_rad_per_s);
    return b < 0 ? nullptr : &windows[static_cast<std::size_t>(b)];
  }
  double settle_s_;
  std::vector<double> edges_;
  const core::Simulation& sim_;
};

std::vector<double> grid_speeds(const Options& o) {
  std::vector<double> w;
  for (int i = 0; i < o.speeds; ++i) {
    w.push_back(o.speeds == 1 ? o.speed_from : o.speed_from + (o.speed_to - o.speed_from) * i / (o.speeds - 1));
  }
  return w;
}

// Runs one (constant or ramp) and returns its rows and Poincare points.
std::vector<Row> run_one(const Run& run, std::size_t total, const Values& base, const Options& o,
                         std::vector<core::PoincarePoint>& points_out) {
  Row proto;
  proto.run_id = run.id;
  proto.runs_total = total;
  proto.direction = run.direction;
  proto.overrides = overrides_text(run.overrides);
  Values values = base;
  for (const auto& [k, v] : run.overrides) values[k] = v;
  const std::vector<double> speeds = grid_speeds(o);
  const double half_bin = speeds.size() > 1 ? 0.5 * (speeds[1] - speeds[0]) : 0.5;
  core::Scene scene;
  try {
    scene = core::scene_from_values(values);
    scene.speed.max_speed_rad_per_s = std::max(scene.speed.max_speed_rad_per_s, o.speed_to);
    if (run.direction == Direction::kConstant) {
      const double revolutions_s = o.revolutions * 2.0 * M_PI / run.speed;
      scene.speed.initial_speed_rad_per_s = scene.speed.target_speed_rad_per_s = run.speed;
      scene.end_time_s = o.settle_s + revolutions_s;
    } else {
      const double start = run.direction == Direction::kUp ? o.speed_from : o.speed_to;
      scene.speed.initial_speed_rad_per_s = scene.speed.target_speed_rad_per_s = start;
      scene.end_time_s = o.settle_s + (o.speed_to - o.speed_from) / o.ramp_accel;
    }
    core::validate_scene(scene);
    proto.solver =
        std::string(core::to_string(scene.solver.method)) + " on " + core::to_string(core::effective_integrator(scene));
  } catch (const std::exception& e) {
    proto.status = "invalid";
    proto.message = e.what();
    proto.friction = std::nan("");
    proto.speed = run.speed;
    return {proto};
  }
  proto.friction = scene.model.friction_coefficient;
  std::vector<double> edges;
  std::vector<double> centres;
  if (run.direction == Direction::kConstant) {
    edges = {run.speed - 1e-9 * run.speed, run.speed + 1e-9 * run.speed};
    centres = {run.speed};
  } else {
    for (double w : speeds) {
      if (edges.empty()) edges.push_back(w - half_bin);
      edges.push_back(w + half_bin);
      centres.push_back(w);
    }
  }
  core::Simulation sim(scene);
  BinnedRecorder rec(o.settle_s, edges, sim);
  bool ok = sim.advance_to(o.settle_s, rec);
  if (ok && run.direction != Direction::kConstant) {
    sim.command_speed(run.direction == Direction::kUp ? o.speed_to : o.speed_from, o.ramp_accel);
  }
  if (ok) ok = sim.advance_to(scene.end_time_s, rec);
  std::vector<Row> rows;
  for (std::size_t b = 0; b < rec.windows.size(); ++b) {
    const core::ResponseWindow& w = rec.windows[b];
    Row r = proto;
    r.speed = centres[b];
    if (!ok) {
      r.status = core::to_string(sim.failure()->failure_class);
      r.message = sim.failure()->message;
    }
    // A ramp's bin with no samples (beyond the failure, or the end) is no row.
    if (w.samples == 0 && run.direction != Direction::kConstant) continue;
    r.c = core::classify_response(w, scene.model.clearance_m);
    r.max_relative_m = w.max_relative_m;
    r.min_relative_m = w.samples ? w.min_relative_m : std::nan("");
    r.points = w.points.size();
    const std::size_t keep =
        o.points_per_bin > 0 ? std::min(w.points.size(), static_cast<std::size_t>(o.points_per_bin)) : w.points.size();
    points_out.insert(points_out.end(), w.points.end() - static_cast<long>(keep), w.points.end());
    rows.push_back(r);
  }
  if (rows.empty()) {  // a run that failed before any bin: one row says so
    Row r = proto;
    r.speed = run.speed;
    r.status = ok ? "ok" : core::to_string(sim.failure()->failure_class);
    r.message = ok ? "" : sim.failure()->message;
    rows.push_back(r);
  }
  return rows;
}

struct Result {
  std::vector<Row> rows;
  std::vector<core::PoincarePoint> points;
  Run run;
  double friction = 0.0;
};

Options parse(int argc, char** argv) {
  Options o;
  std::vector<std::string> axes;
  std::string shard, directions = "constant,up,down";
  CLI::App app(
      "Bifurcation diagrams: over a speed range, the Poincare points (rotor minus stator at each keyphasor, "
      "after settling) and the class of the motion at each speed, from constant-speed runs and from slow "
      "run-up and run-down ramps, over a grid of scene parameters. One CSV row per classified (run, speed), "
      "the points in OUT.csv.points.csv.",
      "rotor_rub_bifurcation");
  std::vector<CLI::Option*> run_options;
  run_options.push_back(app.add_option("--scene", o.scene_path,
                                       "the base scene (default: the package's config/paper_runup.yaml, found from "
                                       "any directory)")
                            ->type_name("FILE")
                            ->check(cli::existing_file()));
  run_options.push_back(app.add_option("--grid", o.grid_path,
                                       "YAML documents of scene keys to value lists: the parameter grid (e.g. "
                                       "friction_coefficient: [0.05, 0.1, 0.2, 0.3])")
                            ->type_name("FILE")
                            ->check(cli::existing_file()));
  run_options.push_back(app.add_option("--set", axes, "adds a parameter axis of scene key values; repeatable")
                            ->type_name("KEY=V1,V2,...")
                            ->allow_extra_args(false));
  run_options.push_back(
      app.add_option(
             "--out", o.out_path,
             "the classes CSV to write (the points go to OUT.csv.points.csv: this name with .points.csv appended); "
             "required")
          ->type_name("FILE.csv"));
  run_options.push_back(app.add_option("--speed-from", o.speed_from, "the lowest speed [rad/s]")
                            ->type_name("W")
                            ->check(cli::number_in(0, 1e5, true))
                            ->capture_default_str());
  run_options.push_back(app.add_option("--speed-to", o.speed_to, "the highest speed [rad/s]")
                            ->type_name("W")
                            ->check(cli::number_in(0, 1e5, true))
                            ->capture_default_str());
  run_options.push_back(app.add_option("--speeds", o.speeds, "speeds on the grid, ends included [-]")
                            ->type_name("N")
                            ->check(cli::integer_in(1, 100000))
                            ->capture_default_str());
  run_options.push_back(
      app.add_option("--settle-s", o.settle_s, "simulated time before anything is recorded: the transient's decay [s]")
          ->type_name("S")
          ->check(cli::number_in(0, 1e5))
          ->capture_default_str());
  run_options.push_back(
      app.add_option("--revolutions", o.revolutions, "revolutions recorded after settling in a constant-speed run [-]")
          ->type_name("N")
          ->check(cli::integer_in(1, 1000000))
          ->capture_default_str());
  run_options.push_back(app.add_option("--ramp-accel", o.ramp_accel, "the ramps' angular acceleration [rad/s^2]")
                            ->type_name("A")
                            ->check(cli::number_in(0, 1e5, true))
                            ->capture_default_str());
  run_options.push_back(
      app.add_option("--directions", directions, "which runs: any of constant, up, down, comma-separated")
          ->type_name("LIST")
          ->capture_default_str());
  run_options.push_back(app.add_option("--points-per-bin", o.points_per_bin,
                                       "write only the last N Poincare points of each (run, speed) to "
                                       "OUT.csv.points.csv; 0: all (the classes always use all) [-]")
                            ->type_name("N")
                            ->check(cli::integer_in(0, 1000000))
                            ->capture_default_str());
  run_options.push_back(app.add_option("--jobs", o.jobs, "runs in parallel (default: all cores) [runs]")
                            ->type_name("N")
                            ->check(cli::integer_in(1, 1024)));
  run_options.push_back(app.add_option("--shard", shard, "only runs with id % N == I (0-based); merge with --merge")
                            ->type_name("I/N")
                            ->check(cli::shard_spec()));
  bool no_progress = false;
  run_options.push_back(app.add_flag("--no-progress", no_progress, "accepted for the sweep's interface; no bar here"));
  app.add_flag("--count-runs", o.count_runs, "print the number of runs the grid makes and exit");
  CLI::Option* merge = app.add_option("--merge", o.merge,
                                      "merge shards: OUT.csv (and OUT.csv.points.csv) from the SHARD.csv files (and "
                                      "their .points.csv), in run order; a missing run is an error")
                           ->type_name("OUT.csv SHARD.csv")
                           ->expected(2, -1);
  app.footer("Exit status: 0 done (failed runs are rows); 1 a run threw (a bug); 2 bad input.");
  cli::parse_or_exit(app, argc, argv);
  if (merge->count() > 0) {
    for (const CLI::Option* opt : run_options) {
      if (opt->count() > 0) cli::usage_error(app, opt->get_name() + " excludes --merge (a merge runs nothing)");
    }
    return o;
  }
  if (o.out_path.empty() && !o.count_runs) cli::usage_error(app, "--out FILE.csv is required");
  // One speed needs no range (constant runs only: a ramp needs one).
  const bool one_speed = o.speeds == 1 && directions == "constant";
  if (!(o.speed_to > o.speed_from) && !(one_speed && o.speed_to == o.speed_from)) {
    cli::usage_error(app, "--speed-to " + num(o.speed_to) + " is out of range; accepted: above --speed-from " +
                              num(o.speed_from) + " (equal with --speeds 1 --directions constant)");
  }
  o.constant = o.up = o.down = false;
  std::stringstream ss(directions);
  for (std::string d; std::getline(ss, d, ',');) {
    if (d == "constant") {
      o.constant = true;
    } else if (d == "up") {
      o.up = true;
    } else if (d == "down") {
      o.down = true;
    } else {
      cli::usage_error(app, "--directions: value '" + d + "' is not accepted; accepted: constant, up, down");
    }
  }
  try {
    for (const auto& a : axes) o.axes.push_back(tools::parse_axis(a));
  } catch (const std::exception& e) {
    cli::usage_error(app, e.what());
  }
  if (!shard.empty()) {
    unsigned si = 0, sn = 0;
    std::sscanf(shard.c_str(), "%u/%u", &si, &sn);
    o.shard_index = si;
    o.shard_count = sn;
  }
  if (o.scene_path.empty()) {
    try {
      o.scene_path = cli::find_package_file("config/paper_runup.yaml");
    } catch (const std::exception& e) {
      cli::usage_error(app, std::string("no default scene: ") + e.what() + "; give --scene FILE");
    }
  }
  return o;
}

// OUT.csv and OUT.csv.points.csv from the shards', rows in run order; every run
// of the grid must be in exactly one shard.
void merge(const std::vector<std::string>& args) {
  const std::string out = args[0];
  std::map<std::size_t, std::vector<std::string>> rows, points;
  std::map<std::size_t, std::size_t> shard_of;  // run id -> the argument it came from
  std::size_t total = 0;
  for (std::size_t i = 1; i < args.size(); ++i) {
    for (const bool pts : {false, true}) {
      const std::string path = pts ? args[i] + ".points.csv" : args[i];
      std::ifstream in(path);
      if (!in) throw std::runtime_error("cannot read shard '" + path + "'");
      std::string line;
      if (!std::getline(in, line) || line != (pts ? kPointHeader : kRowHeader)) {
        throw std::runtime_error("'" + path + "' is not a rotor_rub_bifurcation " + (pts ? "points " : "") + "CSV");
      }
      while (std::getline(in, line)) {
        const std::size_t id = std::stoul(line.substr(0, line.find(',')));
        if (!pts) {
          const std::size_t c1 = line.find(',');
          total = std::stoul(line.substr(c1 + 1, line.find(',', c1 + 1) - c1 - 1));
          const auto seen = shard_of.emplace(id, i);
          if (seen.first->second != i) {
            throw std::runtime_error("run " + std::to_string(id) + " is in two shards ('" + args[seen.first->second] +
                                     "' and '" + args[i] + "')");
          }
        }
        (pts ? points : rows)[id].push_back(line);
      }
    }
  }
  for (std::size_t id = 0; id < total; ++id) {
    if (!rows.count(id)) throw std::runtime_error("run " + std::to_string(id) + " is in no shard");
  }
  std::ofstream o(out), op(out + ".points.csv");
  if (!o || !op) throw std::runtime_error("cannot write '" + out + "'");
  o << kRowHeader << '\n';
  for (const auto& [id, lines] : rows)
    for (const auto& l : lines) o << l << '\n';
  op << kPointHeader << '\n';
  for (const auto& [id, lines] : points)
    for (const auto& l : lines) op << l << '\n';
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  if (!o.merge.empty()) {
    try {
      merge(o.merge);
    } catch (const std::exception& e) {
      std::cerr << "rotor_rub_bifurcation: " << e.what() << "\n";
      return 2;
    }
    return 0;
  }
  Values base;
  std::vector<Run> runs;
  try {
    base = core::read_scene_values(o.scene_path);
    core::scene_from_values(base);
    const auto docs = o.grid_path.empty() ? std::vector<tools::GridDocument>{} : tools::read_grid_file(o.grid_path);
    for (const auto& point : tools::expand_grid(docs, o.axes)) {
      for (const auto& [key, value] : point.overrides) {
        core::Scene scratch;
        core::set_scene_value(scratch, key, value);  // a bad key or value: bad input, named
      }
      if (o.constant) {
        for (double w : grid_speeds(o)) runs.push_back({runs.size(), point.overrides, Direction::kConstant, w});
      }
      if (o.up) runs.push_back({runs.size(), point.overrides, Direction::kUp, 0.0});
      if (o.down) runs.push_back({runs.size(), point.overrides, Direction::kDown, 0.0});
    }
  } catch (const std::exception& e) {
    std::cerr << "rotor_rub_bifurcation: " << e.what() << "\n";
    return 2;
  }
  if (o.count_runs) {
    std::cout << runs.size() << "\n";
    return 0;
  }
  const std::size_t total = runs.size();
  std::vector<Run> mine;
  for (const auto& r : runs) {
    if (r.id % o.shard_count == o.shard_index) mine.push_back(r);
  }
  std::ofstream out(o.out_path), out_points(o.out_path + ".points.csv");
  if (!out || !out_points) {
    std::cerr << "rotor_rub_bifurcation: cannot write '" << o.out_path << "'\n";
    return 2;
  }
  std::vector<Result> results(mine.size());
  std::atomic<std::size_t> next{0};
  std::mutex error_mutex;
  std::string fatal;
  auto worker = [&] {
    for (std::size_t i; (i = next++) < mine.size();) {
      try {
        results[i].run = mine[i];
        results[i].rows = run_one(mine[i], total, base, o, results[i].points);
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(error_mutex);
        fatal = "run " + std::to_string(mine[i].id) + ": " + e.what();
        next = mine.size();
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned j = 0; j < std::min<std::size_t>(o.jobs, std::max<std::size_t>(mine.size(), 1)); ++j) {
    pool.emplace_back(worker);
  }
  for (auto& t : pool) t.join();
  if (!fatal.empty()) {
    std::cerr << "rotor_rub_bifurcation: " << fatal << "\n";
    return 1;
  }
  out << kRowHeader << '\n';
  out_points << kPointHeader << '\n';
  std::map<std::string, std::size_t> classes;
  std::set<std::string> solvers;  // the valid runs'
  std::size_t rows = 0;
  for (const auto& res : results) {
    for (const auto& r : res.rows) {
      write_row(out, r);
      if (!r.solver.empty()) solvers.insert(r.solver);
      ++classes[r.status == "ok" ? core::to_string(r.c.response) : r.status];
      ++rows;
    }
    const char* dir = to_string(res.run.direction);
    const double friction = res.rows.front().friction;
    for (const auto& p : res.points) {
      out_points << res.run.id << ',' << dir << ',' << num(friction) << ',' << num(p.t_s) << ','
                 << num(p.speed_rad_per_s) << ',' << num(p.relative_m.x()) << ',' << num(p.relative_m.y()) << ','
                 << num(p.relative_m.norm()) << ',' << (p.in_contact ? 1 : 0) << ',' << num(p.normal_force_N) << '\n';
    }
  }
  std::string summary, ran;
  for (const auto& [k, n] : classes) summary += " " + k + " " + std::to_string(n);
  for (const auto& solver : solvers) ran += (ran.empty() ? "" : ", ") + solver;
  std::fprintf(stderr, "rotor_rub_bifurcation: %zu runs (shard %zu/%zu of %zu; %s), %zu rows:%s -> %s\n", mine.size(),
               o.shard_index, o.shard_count, total, ran.empty() ? "none valid" : ran.c_str(), rows, summary.c_str(),
               o.out_path.c_str());
  return 0;
}
