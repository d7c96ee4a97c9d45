// A downstream program on the installed core: loads a scene file, runs it for
// 50 ms and checks the samples and the solver's work; the analysis library
// (exported too) records the run as a reference and finds it at no distance
// from itself.
//   rub_downstream SCENE.yaml
#include <cmath>
#include <cstdio>
#include <exception>

#include "rotor_rub_sim/core/run_errors.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/simulation.hpp"

namespace core = rotor_rub::core;

namespace {
struct Count : core::SimulationObserver {
  long samples = 0;
  double last_t_s = -1.0;
  void on_sample(const core::Sample& s) override {
    ++samples;
    last_t_s = s.t_s;
  }
};
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: rub_downstream SCENE.yaml\n");
    return 2;
  }
  try {
    core::Scene scene = core::load_scene(argv[1]);
    scene.end_time_s = 0.05;
    Count count;
    const core::RunResult r = core::run_scene(scene, count);
    if (r.failure) {
      std::fprintf(stderr, "rub_downstream: the run failed: %s\n", r.failure->message.c_str());
      return 1;
    }
    const long grid = std::lround(scene.end_time_s * scene.output_rate_hz);
    if (count.samples < grid || std::abs(count.last_t_s - scene.end_time_s) > 1e-12 || r.stats.steps <= 0) {
      std::fprintf(stderr,
                   "rub_downstream: %ld samples up to t = %g s in %ld steps (expected %ld samples up to %g s)\n",
                   count.samples, count.last_t_s, r.stats.steps, grid, scene.end_time_s);
      return 1;
    }
    const core::ReferenceTrace trace = core::record_reference(scene);
    if (trace.failed || static_cast<long>(trace.t_s.size()) != count.samples ||
        !std::isinf(core::sensitivity_horizon_s(trace, trace, 1e-9))) {
      std::fprintf(stderr, "rub_downstream: the reference trace of the same run differs (%zu samples)\n",
                   trace.t_s.size());
      return 1;
    }
    std::printf("rub_downstream: %ld samples up to t = %g s, %ld steps, method %s\n", count.samples, count.last_t_s,
                r.stats.steps, core::to_string(scene.solver.method));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rub_downstream: %s\n", e.what());
    return 1;
  }
  return 0;
}
