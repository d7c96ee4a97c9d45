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

#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "sweep_csv.hpp"
#include "sweep_reference.hpp"

namespace {

using namespace rotor_rub;
using tools::SweepResult;
using tools::Values;

const char* const kUsage =
    "usage: rotor_rub_sweep [--scene FILE] [--grid FILE] [--set key=v1,v2,...]... --out FILE.csv\n"
    "                       [--repeats N] [--jobs N] [--shard I/N] [--profile] [--cache DIR]\n"
    "                       [--error-rate HZ] [--window-ms MS] [--reference-rtol R] [--reference-atol A]\n"
    "                       [--inaccurate-above M] [--no-progress]\n"
    "       rotor_rub_sweep --merge OUT.csv SHARD.csv...\n"
    "  --grid: YAML documents of scene keys to value lists (see config/sweeps/); --set adds an axis\n"
    "  --shard I/N: only runs with id % N == I (0-based); merge the shards' CSVs with --merge\n"
    "  --repeats: timed runs per grid point, wall time is their median (default 3)\n"
    "  --jobs: runs in parallel (default: all cores); wall times are measured under that load\n"
    "  --profile: one more run per point for the shares of time in derivatives and iteration\n"
    "  --cache DIR: keep reference runs on disk, keyed by their scene and the core's build\n"
    "  --inaccurate-above M: status 'inaccurate' when max |r_r - r_r,ref| > M metres (default 1e-4)\n"
    "exit status: 0 done (failed runs are rows, not errors), 2 bad input\n";

[[noreturn]] void bad_input(const std::string& what) {
  std::cerr << "rotor_rub_sweep: " << what << "\n";
  std::exit(2);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? std::nan("") : v[v.size() / 2];
}

struct Options {
  std::string scene_path = "config/paper_runup.yaml";
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
  const auto ref = refs.get(values);
  if (ref->failed) {
    if (r.status == "ok") r.status = "no_reference";
    r.message += (r.message.empty() ? "" : "; ") + std::string("reference failed: ") + ref->failure_message;
  }
  core::Scene es = r.scene;
  es.output_rate_hz = opt.reference.sample_rate_hz;
  core::ErrorObserver errors(*ref);
  core::run_scene(es, errors);
  r.errors = errors.finish();
  if (r.status == "ok" && !(r.errors.max_rotor_m <= opt.inaccurate_above_m)) {
    r.status = "inaccurate";
    r.message = "max |r_r - r_r,ref| above --inaccurate-above";
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

Options parse(int argc, char** argv) {
  Options o;
  auto value = [&](int& i, const std::string& name) -> std::string {
    if (i + 1 >= argc) bad_input(name + " needs a value\n" + kUsage);
    return argv[++i];
  };
  auto number = [&](int& i, const std::string& name, double lo, double hi) {
    const std::string text = value(i, name);
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0' || !std::isfinite(v) || v < lo || v > hi) {
      bad_input(name + ": '" + text + "' is not accepted; accepted: a number in [" + std::to_string(lo) + ", " +
                std::to_string(hi) + "]");
    }
    return v;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--scene") {
      o.scene_path = value(i, a);
    } else if (a == "--grid") {
      o.grid_path = value(i, a);
    } else if (a == "--set") {
      try {
        o.axes.push_back(tools::parse_axis(value(i, a)));
      } catch (const std::invalid_argument& e) {
        bad_input(e.what());
      }
    } else if (a == "--out") {
      o.out_path = value(i, a);
    } else if (a == "--cache") {
      o.cache_dir = value(i, a);
    } else if (a == "--repeats") {
      o.repeats = static_cast<int>(number(i, a, 1, 1000));
    } else if (a == "--jobs") {
      o.jobs = static_cast<unsigned>(number(i, a, 1, 1024));
    } else if (a == "--shard") {
      const std::string s = value(i, a);
      unsigned si = 0, sn = 0;
      char extra = 0;
      if (std::sscanf(s.c_str(), "%u/%u%c", &si, &sn, &extra) != 2 || sn == 0 || si >= sn) {
        bad_input("--shard: '" + s + "' is not accepted; accepted: I/N with 0 <= I < N");
      }
      o.shard_index = si;
      o.shard_count = sn;
    } else if (a == "--inaccurate-above") {
      o.inaccurate_above_m = number(i, a, 0, 1);
    } else if (a == "--profile") {
      o.profile = true;
    } else if (a == "--no-progress") {
      o.progress = false;
    } else if (a == "--error-rate") {
      o.reference.sample_rate_hz = number(i, a, 1, 1e7);
    } else if (a == "--window-ms") {
      o.reference.window_s = number(i, a, 1e-3, 1e3) * 1e-3;
    } else if (a == "--reference-rtol") {
      o.reference.rtol = number(i, a, 1e-14, 1e-6);
    } else if (a == "--reference-atol") {
      o.reference.atol = number(i, a, 1e-16, 1e-6);
    } else if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      std::exit(0);
    } else {
      bad_input("unknown option '" + a + "'\n" + kUsage);
    }
  }
  if (o.out_path.empty()) bad_input(std::string("--out FILE.csv is required\n") + kUsage);
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && std::string(argv[1]) == "--merge") {
    if (argc < 4) bad_input(std::string("--merge needs OUT.csv and at least one shard\n") + kUsage);
    std::vector<std::string> parts(argv + 3, argv + argc);
    try {
      std::ofstream out(argv[2]);
      if (!out) bad_input(std::string("cannot write '") + argv[2] + "'");
      tools::merge_sweep_csvs(parts, out);
    } catch (const std::exception& e) {
      bad_input(e.what());
    }
    return 0;
  }
  const Options opt = parse(argc, argv);
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
  std::fprintf(stderr, "rotor_rub_sweep: %zu runs (shard %zu/%zu of %zu), %zu ok, %zu not ok -> %s\n", runs.size(),
               opt.shard_index, opt.shard_count, total, ok, runs.size() - ok, opt.out_path.c_str());
  return 0;
}
