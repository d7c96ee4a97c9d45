// rotor_rub_sweep: a grid of independent, deterministic runs of the core on
// all cores, each measured for cost and for error against a reference run
// (switching at rtol 1e-10, once per distinct physics). One CSV row per run.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <mutex>
#include <thread>

#include "cli_options.hpp"
#include "package_paths.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "sweep_csv.hpp"
#include "sweep_reference.hpp"

namespace {

using namespace rotor_rub;
using tools::SweepResult;
using tools::Values;
namespace cli = rotor_rub::cli;

[[noreturn]] void bad_input(const std::string& what) {
  std::cerr << "rotor_rub_sweep: " << what << "\n";
  std::exit(2);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? std::nan("") : v[v.size() / 2];
}

struct Options {
  std::string scene_path;  // default: the package's config/paper_runup.yaml
  std::string grid_path, out_path, cache_dir;
  std::vector<tools::GridAxis> axes;
  int repeats = 3;
  unsigned jobs = std::max(1u, std::thread::hardware_concurrency());
  std::size_t shard_index = 0, shard_count = 1;
  bool profile = false, progress = true;
  // A run that completes with max |r_r - r_r,ref| above this is "inaccurate":
  // 5 % of the paper's 2 mm clearance.
  double inaccurate_above_m = 1e-4;
  tools::ReferenceSettings reference;
};

SweepResult run_one(const tools::SweepRun& run, std::size_t total, const Values& base, const Options& opt,
                    tools::ReferenceStore& refs) {
  SweepResult r;
  r.id = run.id;
  r.runs_total = total;
  r.overrides = run.overrides;
  r.failure_time_s = std::nan("");
  r.rhs_share = r.iteration_share = std::nan("");
  Values values = base;
  for (const auto& [k, v] : run.overrides) values[k] = v;
  try {
    r.scene = core::scene_from_values(values);
  } catch (const core::SceneError& e) {
    r.status = "invalid";
    r.message = e.what();
    return r;
  }
  // Cost: the whole scene as the runner does it, no samples kept.
  std::vector<double> walls;
  core::RunResult timed;
  for (int i = 0; i < opt.repeats; ++i) {
    core::SimulationObserver none;
    timed = core::run_scene(r.scene, none);
    walls.push_back(timed.stats.wall_time_s);
  }
  r.repeats = opt.repeats;
  r.wall_time_s = median(walls);
  r.stats = timed.stats;
  r.status = "ok";
  if (timed.failure) {
    r.status = core::to_string(timed.failure->failure_class);
    r.failure_time_s = timed.failure->time_s;
    r.message = timed.failure->message;
  }
  if (opt.profile) {
    core::Scene ps = r.scene;
    ps.solver.profile_cost = true;
    core::SimulationObserver none;
    const core::RunResult prof = core::run_scene(ps, none);
    r.rhs_share = (prof.stats.rhs_time_s - prof.stats.iteration_time_s) / prof.stats.wall_time_s;
    r.iteration_share = prof.stats.iteration_time_s / prof.stats.wall_time_s;
  }
  // Error: the same run sampled on the reference's grid (a failed run
  // compares the samples it delivered).
  const tools::Judged judged = refs.judge(values, r.scene.solver.atol);
  const auto& ref = judged.reference;
  if (ref->failed) {
    if (r.status == "ok") r.status = "no_reference";
    r.message += (r.message.empty() ? "" : "; ") + std::string("reference failed: ") + ref->failure_message;
  }
  core::Scene es = r.scene;
  es.output_rate_hz = opt.reference.sample_rate_hz;
  core::ErrorObserver errors(*ref, judged.horizon_s);
  core::run_scene(es, errors);
  r.errors = errors.finish();
  r.horizon_s = judged.horizon_s;
  if (!judged.witness_failures.empty()) {
    r.message += (r.message.empty() ? "" : "; ") + std::string("witness failed: ") + judged.witness_failures;
  }
  if (r.status == "ok" && !(r.errors.max_rotor_in_horizon_m <= opt.inaccurate_above_m)) {
    r.status = "inaccurate";
    r.message =
        std::string(std::isfinite(judged.horizon_s) ? "max |r_r - r_r,ref| before the horizon above --inaccurate-above"
                                                    : "max |r_r - r_r,ref| above --inaccurate-above") +
        (r.message.empty() ? "" : "; " + r.message);
  }
  return r;
}

class Progress {
 public:
  Progress(std::size_t total, bool on) : total_(total), on_(on && ::isatty(2)), start_(clock::now()) {}
  void done_one() {
    const std::size_t d = ++done_;
    if (!on_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    const double el = std::chrono::duration<double>(clock::now() - start_).count();
    const double eta = el / static_cast<double>(d) * static_cast<double>(total_ - d);
    const int width = 30, filled = static_cast<int>(width * d / std::max<std::size_t>(total_, 1));
    std::fprintf(stderr, "\r[%s%s] %zu/%zu runs  %.0f s elapsed  eta %.0f s ", std::string(filled, '#').c_str(),
                 std::string(width - filled, ' ').c_str(), d, total_, el, eta);
    if (d == total_) std::fprintf(stderr, "\n");
  }

 private:
  using clock = std::chrono::steady_clock;
  std::size_t total_;
  bool on_;
  clock::time_point start_;
  std::atomic<std::size_t> done_{0};
  std::mutex mutex_;
};

// I/N with 0 <= I < N.
// key=v1,v2,...: one axis of the grid.
CLI::Validator axis_spec() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        try {
          tools::parse_axis(s);
        } catch (const std::invalid_argument& e) {
          return e.what();
        }
        return std::string();
      },
      "", "axis");
}

struct Parsed {
  Options options;
  std::vector<std::string> merge;  // OUT.csv SHARD.csv...: merge, run nothing
  bool count_runs = false;         // print the grid's number of runs, run nothing
};

Parsed parse(int argc, char** argv) {
  Parsed p;
  Options& o = p.options;
  std::vector<std::string> axes;
  std::string shard;
  double window_ms = o.reference.window_s * 1e3;
  CLI::App app(
      "A grid of independent, deterministic runs of the core on all cores, each measured for cost and for error "
      "against a reference run (switching at --reference-rtol, once per distinct physics). One CSV row per run.",
      "rotor_rub_sweep");
  std::vector<CLI::Option*> run_options;
  run_options.push_back(app.add_option("--scene", o.scene_path,
                                       "the base scene file (default: the package's config/paper_runup.yaml, "
                                       "found from any directory)")
                            ->type_name("FILE")
                            ->check(cli::existing_file()));
  run_options.push_back(
      app.add_option("--grid", o.grid_path, "YAML documents of scene keys to value lists (see config/sweeps/)")
          ->type_name("FILE")
          ->check(cli::existing_file()));
  run_options.push_back(app.add_option("--set", axes, "adds an axis of scene key values to the grid; repeatable")
                            ->type_name("KEY=V1,V2,...")
                            ->allow_extra_args(false)
                            ->check(axis_spec()));
  run_options.push_back(
      app.add_option("--out", o.out_path, "the CSV to write, one row per run; required")->type_name("FILE.csv"));
  run_options.push_back(
      app.add_option("--repeats", o.repeats, "timed runs per grid point; wall time is their median [runs]")
          ->type_name("N")
          ->check(cli::integer_in(1, 1000))
          ->capture_default_str());
  run_options.push_back(app.add_option("--jobs", o.jobs,
                                       "runs in parallel (default: all cores, " + std::to_string(o.jobs) +
                                           " here); wall times are measured under that load [runs]")
                            ->type_name("N")
                            ->check(cli::integer_in(1, 1024)));
  run_options.push_back(
      app.add_option("--shard", shard, "only runs with id % N == I (0-based); merge the shards' CSVs with --merge")
          ->type_name("I/N")
          ->check(cli::shard_spec()));
  run_options.push_back(app.add_flag("--profile", o.profile,
                                     "one more run per point for the shares of time in derivatives and iteration"));
  run_options.push_back(app.add_option("--cache", o.cache_dir,
                                       "keep reference runs on disk in DIR, keyed by their scene and the core's build")
                            ->type_name("DIR"));
  run_options.push_back(app.add_option("--error-rate", o.reference.sample_rate_hz,
                                       "the grid the errors are measured on, in simulated time [Hz]")
                            ->type_name("HZ")
                            ->check(cli::number_in(1, 1e7))
                            ->capture_default_str());
  run_options.push_back(app.add_option("--window-ms", window_ms, "the windows the contact impulse is compared in [ms]")
                            ->type_name("MS")
                            ->check(cli::number_in(1e-3, 1e3))
                            ->capture_default_str());
  run_options.push_back(app.add_option("--reference-rtol", o.reference.rtol, "the reference's rtol [-]")
                            ->type_name("R")
                            ->check(cli::number_in(1e-14, 1e-6))
                            ->capture_default_str());
  run_options.push_back(app.add_option("--reference-atol", o.reference.atol, "the reference's atol [m, m/s]")
                            ->type_name("A")
                            ->check(cli::number_in(1e-16, 1e-6))
                            ->capture_default_str());
  run_options.push_back(app.add_option("--inaccurate-above", o.inaccurate_above_m,
                                       "status 'inaccurate' when max |r_r - r_r,ref| is above this [m]")
                            ->type_name("M")
                            ->check(cli::number_in(0, 1))
                            ->capture_default_str());
  run_options.push_back(app.add_flag(
      "--witness", o.reference.witness,
      "judge each run ('inaccurate', event columns) only up to where the first of these parts from the reference "
      "by --inaccurate-above (column horizon_s): the reference with the bore moved by the run's atol, and the "
      "switching and iteration methods on dop853 at the reference's tolerances; past it the motion is not "
      "determined at the run's precision (chaos, grazing impacts)"));
  bool no_progress = false;
  run_options.push_back(
      app.add_flag("--no-progress", no_progress, "no progress bar (there is one on a terminal only)"));
  app.add_flag("--count-runs", p.count_runs,
               "print the number of runs the grid makes (all shards) and exit; scripts/slurm_sweep.sh sizes its "
               "shards with it");
  CLI::Option* merge = app.add_option("--merge", p.merge,
                                      "merge shards: writes OUT.csv with the rows of the SHARD.csv files in run "
                                      "order (a missing run is an error); runs nothing")
                           ->type_name("OUT.csv SHARD.csv")
                           ->expected(2, -1);
  app.footer("Exit status: 0 done (failed runs are rows, not errors); 1 a run threw (a bug); 2 bad input.");
  cli::parse_or_exit(app, argc, argv);
  if (merge->count() > 0) {
    // Checked here, not with CLI11's excludes(): that lists --merge on every option of the help.
    for (const CLI::Option* opt : run_options) {
      if (opt->count() > 0) cli::usage_error(app, opt->get_name() + " excludes --merge (a merge runs nothing)");
    }
    return p;
  }
  if (o.out_path.empty() && !p.count_runs) cli::usage_error(app, "--out FILE.csv is required");
  for (const auto& a : axes) o.axes.push_back(tools::parse_axis(a));
  if (!shard.empty()) {
    unsigned si = 0, sn = 0;
    std::sscanf(shard.c_str(), "%u/%u", &si, &sn);
    o.shard_index = si;
    o.shard_count = sn;
  }
  o.reference.window_s = window_ms * 1e-3;
  o.reference.horizon_apart_m = o.inaccurate_above_m;
  o.progress = !no_progress;
  if (o.scene_path.empty()) {
    try {
      o.scene_path = cli::find_package_file("config/paper_runup.yaml");
    } catch (const std::exception& e) {
      bad_input(std::string("no default scene: ") + e.what() + "; give --scene FILE");
    }
  }
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  const Parsed parsed = parse(argc, argv);
  if (!parsed.merge.empty()) {
    const std::vector<std::string> parts(parsed.merge.begin() + 1, parsed.merge.end());
    try {
      std::ofstream out(parsed.merge[0]);
      if (!out) bad_input("cannot write '" + parsed.merge[0] + "'");
      tools::merge_sweep_csvs(parts, out);
    } catch (const std::exception& e) {
      bad_input(e.what());
    }
    return 0;
  }
  const Options& opt = parsed.options;
  Values base;
  std::vector<tools::SweepRun> runs;
  try {
    base = core::read_scene_values(opt.scene_path);
    core::scene_from_values(base);  // the base scene itself must be valid
    const auto docs = opt.grid_path.empty() ? std::vector<tools::GridDocument>{} : tools::read_grid_file(opt.grid_path);
    runs = tools::expand_grid(docs, opt.axes);
    // A typo in a grid key is a bad grid, not a row of invalid runs.
    for (const auto& run : runs) {
      for (const auto& override_kv : run.overrides) {
        // A named reference, not a structured binding: C++17 lambdas cannot
        // capture structured bindings (clang rejects it; C++20 allows it).
        const std::string& key = override_kv.first;
        const auto& keys = core::scene_keys();
        const bool known =
            std::any_of(keys.begin(), keys.end(), [&](const core::SceneKeyInfo& k) { return k.key == key; });
        if (!known) {
          const std::string near = core::nearest_scene_key(key);
          throw std::invalid_argument("grid key '" + key + "' is not a scene key" +
                                      (near.empty() ? "" : " (did you mean '" + near + "'?)") +
                                      "; rotor_rub_run --list-keys prints them");
        }
      }
    }
  } catch (const std::exception& e) {
    bad_input(e.what());
  }
  if (parsed.count_runs) {
    std::cout << runs.size() << "\n";
    return 0;
  }
  const std::size_t total = runs.size();
  runs = tools::select_shard(runs, opt.shard_index, opt.shard_count);
  std::ofstream out(opt.out_path);
  if (!out) bad_input("cannot write '" + opt.out_path + "'");

  tools::ReferenceStore refs(opt.reference, opt.cache_dir);
  std::vector<SweepResult> results(runs.size());
  std::atomic<std::size_t> next{0};
  Progress progress(runs.size(), opt.progress);
  std::mutex error_mutex;
  std::string fatal;
  auto worker = [&] {
    for (std::size_t i; (i = next++) < runs.size();) {
      try {
        results[i] = run_one(runs[i], total, base, opt, refs);
      } catch (const std::exception& e) {
        // A bug, not a method failure (those are rows): stop the sweep loudly.
        std::lock_guard<std::mutex> lock(error_mutex);
        fatal = "run " + std::to_string(runs[i].id) + ": " + e.what();
        next = runs.size();
      }
      progress.done_one();
    }
  };
  std::vector<std::thread> pool;
  for (unsigned j = 0; j < std::min<std::size_t>(opt.jobs, std::max<std::size_t>(runs.size(), 1)); ++j) {
    pool.emplace_back(worker);
  }
  for (auto& t : pool) t.join();
  if (!fatal.empty()) {
    std::cerr << "rotor_rub_sweep: " << fatal << "\n";
    return 1;
  }
  out << tools::sweep_csv_header() << '\n';
  std::size_t ok = 0;
  for (const auto& r : results) {
    tools::write_sweep_row(out, r);
    ok += r.status == "ok";
  }
  std::fprintf(stderr, "rotor_rub_sweep: %zu runs (shard %zu/%zu of %zu), %zu ok, %zu not ok -> %s (scene %s)\n",
               runs.size(), opt.shard_index, opt.shard_count, total, ok, runs.size() - ok, opt.out_path.c_str(),
               opt.scene_path.c_str());
  return 0;
}
