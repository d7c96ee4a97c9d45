// Shared helpers of the core tests.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <initializer_list>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "rotor_rub_sim/core/contact_method.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "rotor_rub_sim/core/solver_registry.hpp"

namespace rotor_rub::test {

inline std::string source_path(const std::string& rel) { return std::string(ROTOR_RUB_SOURCE_DIR) + "/" + rel; }

inline core::Scene paper_scene() { return core::load_scene(source_path("config/paper_runup.yaml")); }

// The paper scene's model with another stator and friction coefficient.
inline core::ModelParameters paper_model(core::StatorModel stator, double friction_coefficient) {
  core::ModelParameters p = paper_scene().model;
  p.stator_model = stator;
  p.friction_coefficient = friction_coefficient;
  return p;
}

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

// The method on dopri5 (the paper's ode45 scheme), the integrator every
// method runs on: the tests written for one integrator name it; the shared
// suites run every pair of the registry (all_solvers).
inline core::Scene with_method(core::Scene s, core::Method m, double rtol, double atol) {
  s.solver.method = m;
  s.solver.integrator = core::Integrator::kDopri5;
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

// The registry's pairs (solver_registry.hpp) of the given methods, but rk4:
// its fixed step has no tolerance, and the suites run at tolerances
// (test_fixed_step.cpp runs it).
inline std::vector<Solver> registry_solvers(std::initializer_list<core::Method> methods) {
  std::vector<Solver> v;
  for (const core::Method m : methods) {
    for (const core::SolverEntry& e : core::solver_registry()) {
      if (e.method == m && e.integrator != core::Integrator::kRk4) v.push_back({e.method, e.integrator});
    }
  }
  return v;
}
// The rigid methods on every integrator each runs on.
inline std::vector<Solver> rigid_solvers() {
  return registry_solvers({core::Method::kSwitching, core::Method::kIteration});
}
// Every method on every integrator of the registry but rk4 (the Jeffcott's
// and a flexible rotor's alike; rk4 runs at a fixed step below the rotor's
// bound: test_fixed_step.cpp, test_flexible_rk4.cpp).
inline std::vector<Solver> all_solvers() {
  return registry_solvers({core::Method::kSwitching, core::Method::kIteration, core::Method::kPenalty});
}

// A contact method driven alone, without Simulation (and so without
// validate_scene), as a core user who builds one with make_contact_method
// does, until it fails or reaches the scene's end (the drive's first segment
// must reach it). The failure it threw, if any.
struct MethodAloneFailure {
  core::FailureClass failure_class;
  double time_s;
  std::string message;
};
inline std::optional<MethodAloneFailure> run_method_alone(const core::Scene& s) {
  const std::unique_ptr<core::ContactMethod> method = core::make_contact_method(s);
  const core::SpeedProfile profile(s.speed);
  method->start(0.0, core::JeffcottModel(s.model).initial_kinematics(profile.at(0.0)), profile.segment_at(0.0));
  std::vector<core::ContactEvent> events;
  try {
    while (method->step_end() < s.end_time_s) method->step(s.end_time_s, events);
  } catch (const core::MethodFailure& f) {
    return MethodAloneFailure{f.failure_class, f.time_s, f.what()};
  }
  return std::nullopt;
}

inline core::Scene with_method(core::Scene s, const Solver& m, double rtol, double atol) {
  s = with_method(std::move(s), m.method, rtol, atol);
  s.solver.integrator = m.integrator;
  return s;
}

// A method of the rigid contact (dop853 at rtol 1e-10) started on the free
// layout's state x (the rotor's position, the elastic stator's, their
// velocities: periodic_orbit.hpp) at t = 0 under the constant speed w: its
// states at `times` (increasing), in x's layout.
inline std::vector<Eigen::VectorXd> method_states(core::Method method, const core::ModelParameters& p, double w,
                                                  const Eigen::VectorXd& x, const std::vector<double>& times) {
  core::Scene s;
  s.model = p;
  s.solver.method = method;
  s.solver.integrator = core::Integrator::kDop853;
  s.solver.rtol = 1e-10;
  s.solver.atol = 1e-14;
  s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = w;
  s.speed.acceleration_rad_per_s2 = 0.0;
  s.end_time_s = times.back();
  const core::SpeedProfile profile(s.speed);
  const std::unique_ptr<core::ContactMethod> m = core::make_contact_method(s);
  const int v = static_cast<int>(x.size()) / 2;
  const bool elastic = x.size() == 8;
  core::Kinematics k;
  k.rotor_pos = x.head<2>();
  k.rotor_vel = x.segment<2>(v);
  if (elastic) {
    k.stator_pos = x.segment<2>(2);
    k.stator_vel = x.segment<2>(v + 2);
  }
  m->start(0.0, k, profile.segment_at(0.0));
  std::vector<core::ContactEvent> events;
  m->change_model(0.0, p, events);  // a start on the bore: decided as at a touchdown without closing speed
  std::vector<Eigen::VectorXd> out;
  for (const double t : times) {
    while (m->step_end() < t) m->step(times.back(), events);
    const core::Kinematics at = m->sample(t).kin;
    Eigen::VectorXd y(x.size());
    y.head<2>() = at.rotor_pos;
    y.segment<2>(v) = at.rotor_vel;
    if (elastic) {
      y.segment<2>(2) = at.stator_pos;
      y.segment<2>(v + 2) = at.stator_vel;
    }
    out.push_back(y);
  }
  return out;
}

// |x| in units of C (positions) and C w (velocities) of the free layout.
inline double scaled_norm(const Eigen::VectorXd& x, const core::ModelParameters& p, double w) {
  const int v = static_cast<int>(x.size()) / 2;
  return std::max(x.head(v).cwiseAbs().maxCoeff() / p.clearance_m,
                  x.tail(v).cwiseAbs().maxCoeff() / (p.clearance_m * w));
}

}  // namespace rotor_rub::test
