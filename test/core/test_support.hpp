// Shared helpers of the core tests.
#pragma once

#include <string>
#include <vector>

#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/simulation.hpp"

namespace rotor_rub::test {

inline std::string source_path(const std::string& rel) { return std::string(ROTOR_RUB_SOURCE_DIR) + "/" + rel; }

inline core::Scene paper_scene() { return core::load_scene(source_path("config/paper_runup.yaml")); }

struct Collect : core::SimulationObserver {
  std::vector<core::Sample> samples;
  std::vector<core::ContactEvent> events;
  void on_sample(const core::Sample& s) override { samples.push_back(s); }
  void on_event(const core::ContactEvent& e) override { events.push_back(e); }
};

struct Run {
  Collect out;
  core::RunResult result;
};

inline Run run(const core::Scene& s) {
  Run r;
  r.result = core::run_scene(s, r.out);
  return r;
}

inline core::Scene with_method(core::Scene s, core::Method m, double rtol, double atol) {
  s.solver.method = m;
  s.solver.rtol = rtol;
  s.solver.atol = atol;
  return s;
}

}  // namespace rotor_rub::test
