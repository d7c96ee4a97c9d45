// Shared helpers of the core tests.
#pragma once

#include <ostream>
#include <string>
#include <utility>
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

// A contact method with its time integrator: the shared suites run every
// physics test over each (as Drake runs its suites over all integrators).
struct Solver {
  core::Method method = core::Method::kSwitching;
  core::Integrator integrator = core::Integrator::kDopri5;
  // The test name: the method, and the integrator unless dopri5.
  std::string name() const {
    std::string n = core::to_string(method);
    if (integrator != core::Integrator::kDopri5) n += std::string("_") + core::to_string(integrator);
    return n;
  }
};
inline void PrintTo(const Solver& s, std::ostream* os) { *os << s.name(); }

// The rigid methods on every integrator each accepts (switching: dopri5,
// rkf78 and dop853; iteration: dopri5 and dop853).
inline std::vector<Solver> rigid_solvers() {
  using core::Integrator;
  using core::Method;
  return {{Method::kSwitching, Integrator::kDopri5},
          {Method::kSwitching, Integrator::kRkf78},
          {Method::kSwitching, Integrator::kDop853},
          {Method::kIteration, Integrator::kDopri5},
          {Method::kIteration, Integrator::kDop853}};
}
inline std::vector<Solver> all_solvers() {
  std::vector<Solver> v = rigid_solvers();
  v.push_back({core::Method::kPenalty, core::Integrator::kDopri5});
  v.push_back({core::Method::kPenalty, core::Integrator::kRosenbrock4});
  return v;
}

inline core::Scene with_method(core::Scene s, const Solver& m, double rtol, double atol) {
  s = with_method(std::move(s), m.method, rtol, atol);
  s.solver.integrator = m.integrator;
  return s;
}

}  // namespace rotor_rub::test
