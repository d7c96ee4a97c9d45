// The registry of methods and integrators (solver_registry.hpp): what auto
// resolves to, that every row builds and runs the scene, that validation and
// the factory agree with it, and that a run reports the integrator it ran.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "rotor_rub_sim/core/contact_method.hpp"
#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/solver_registry.hpp"
#include "sweep_grid.hpp"
#include "test_support.hpp"

namespace rotor_rub {
namespace {

using core::Integrator;
using core::Method;

TEST(SolverRegistry, AutoIsDop853UpToRtol1e4ThenDopri5AndRosenbrock4ForPenalty) {
  const auto flexible = core::RotorKind::kFlexible;
  for (const Method m : {Method::kSwitching, Method::kIteration}) {
    for (const double rtol : {1e-10, 1e-6, 1e-4}) {
      EXPECT_EQ(core::auto_integrator(m, rtol), Integrator::kDop853);
      // A flexible rotor's free flight goes to RODASP where its modes make dop853's steps stiff.
      EXPECT_EQ(core::auto_integrator(m, rtol, flexible), Integrator::kDop853Rosenbrock4);
    }
    for (const double rtol : {1.01e-4, 1e-3, 1e-2, 1.0}) {
      EXPECT_EQ(core::auto_integrator(m, rtol), Integrator::kDopri5);
      EXPECT_EQ(core::auto_integrator(m, rtol, flexible), Integrator::kDopri5);
    }
  }
  for (const double rtol : {1e-10, 1e-6, 1e-3, 1.0}) {
    EXPECT_EQ(core::auto_integrator(Method::kPenalty, rtol), Integrator::kRosenbrock4);
    EXPECT_EQ(core::auto_integrator(Method::kPenalty, rtol, flexible), Integrator::kRosenbrock4);
  }
  core::SolverSettings s;
  EXPECT_EQ(s.integrator, Integrator::kAuto);  // the default
  s.method = Method::kSwitching;
  s.rtol = 1e-3;
  EXPECT_EQ(core::effective_integrator(s), Integrator::kDopri5);
  s.integrator = Integrator::kRkf78;  // a named one is itself
  EXPECT_EQ(core::effective_integrator(s), Integrator::kRkf78);
}

// The integrator key's description (--help, the template, docs/node.md) is
// written from the table: it says what auto_integrator does.
TEST(SolverRegistry, TheAutoTextSaysWhatAutoPicks) {
  const std::string text = core::auto_integrator_text();
  EXPECT_EQ(text,
            "penalty rosenbrock4; switching dop853 up to rtol 1e-4, dopri5 above, dop853_rosenbrock4 up to rtol "
            "1e-4, dopri5 above with a rotor_file; iteration dop853 up to rtol 1e-4, dopri5 above, dop853_rosenbrock4 "
            "up to rtol 1e-4, dopri5 above with a rotor_file");
  const core::SceneKeyInfo* key = nullptr;
  for (const core::SceneKeyInfo& k : core::scene_keys()) {
    if (k.key == "integrator") key = &k;
  }
  ASSERT_NE(key, nullptr);
  EXPECT_NE(key->description.find(text), std::string::npos) << key->description;
  core::Scene flexible;
  flexible.solver.method = Method::kPenalty;
  flexible.rotor.file = "rotor.yaml";  // auto's pick depends only on whether there is one
  EXPECT_EQ(core::effective_integrator(flexible), Integrator::kRosenbrock4);  // as the text says
  flexible.solver.method = Method::kSwitching;
  EXPECT_EQ(core::effective_integrator(flexible), Integrator::kDop853Rosenbrock4);
}

TEST(SolverRegistry, EveryRowIsOfferedOnceAndEveryOtherPairRefused) {
  std::set<std::pair<Method, Integrator>> rows;
  for (const core::SolverEntry& e : core::solver_registry()) {
    EXPECT_TRUE(rows.insert({e.method, e.integrator}).second) << core::to_string(e.integrator) << " twice";
    EXPECT_NE(e.integrator, Integrator::kAuto);
    for (const auto make : e.make) EXPECT_NE(make, nullptr);
    EXPECT_GT(std::string(e.note).size(), 10u);
  }
  for (const Method m : core::kAllMethods) {
    for (const Integrator i : core::kAllIntegrators) {
      if (i == Integrator::kAuto) continue;
      core::Scene s;
      s.solver.method = m;
      s.solver.integrator = i;
      if (i == Integrator::kRk4) s.solver.fixed_step_s = 1e-6;  // below its stability bound
      const bool offered = rows.count({m, i}) > 0;
      EXPECT_EQ(core::find_solver(m, i) != nullptr, offered);
      if (offered) {
        EXPECT_NO_THROW(core::validate_scene(s)) << core::to_string(m) << " " << core::to_string(i);
      } else {
        EXPECT_THROW(core::validate_scene(s), core::SceneError) << core::to_string(m) << " " << core::to_string(i);
        EXPECT_THROW(core::Simulation{s}, core::SceneError) << core::to_string(m) << " " << core::to_string(i);
      }
    }
  }
}

// The work-precision chart (docs/studies.md) draws every pair the registry
// offers with a tolerance to sweep (rk4 steps at a fixed size): its grid
// names each of them and no other, so a row added to the registry fails here
// until the chart's sweep has it. dop853_rosenbrock4 is dop853 on the
// chart's paper scene (no stiff free flight there:
// EveryRowRunsThePaperScenesFirstContact), so it is not drawn twice.
TEST(SolverRegistry, TheWorkPrecisionGridHasEveryAdaptivePair) {
  auto name = [](Method m, Integrator i) { return std::string(core::to_string(m)) + "/" + core::to_string(i); };
  std::set<std::string> grid;
  const auto docs = tools::read_grid_file(test::source_path("config/sweeps/work_precision.yaml"));
  for (const tools::SweepRun& run : tools::expand_grid(docs, {})) {
    grid.insert(name(core::method_from_string(run.overrides.at("method")),
                     core::integrator_from_string(run.overrides.at("integrator"))));
  }
  std::set<std::string> offered;
  for (const core::SolverEntry& e : core::solver_registry()) {
    if (e.integrator != Integrator::kRk4 && e.integrator != Integrator::kDop853Rosenbrock4) {
      offered.insert(name(e.method, e.integrator));
    }
  }
  EXPECT_EQ(grid, offered);
}

// The registry's third dimension: each row's factory for a kind of rotor
// builds the method on that kind (a flexible rotor's method has its model),
// and make_contact_method takes the scene's.
TEST(SolverRegistry, EveryRowBuildsItsMethodForEachKindOfRotor) {
  core::Scene flexible = core::load_scene(test::source_path("config/seal_rub_runup.yaml"));
  core::load_rotor(flexible);  // read once for every row
  for (const core::SolverEntry& e : core::solver_registry()) {
    for (const core::RotorKind r : core::kAllRotorKinds) {
      core::Scene s = r == core::RotorKind::kJeffcott ? test::paper_scene() : flexible;
      s.solver.method = e.method;
      s.solver.integrator = e.integrator;
      ASSERT_EQ(core::rotor_kind(s), r);
      const auto method = e.make[static_cast<std::size_t>(r)](s);
      ASSERT_NE(method, nullptr);
      EXPECT_EQ(method->flexible_rotor() != nullptr, r == core::RotorKind::kFlexible)
          << core::to_string(e.method) << " on " << core::to_string(e.integrator) << ", " << core::to_string(r);
    }
  }
  EXPECT_NE(core::make_contact_method(flexible)->flexible_rotor(), nullptr);
  EXPECT_EQ(core::make_contact_method(test::paper_scene())->flexible_rotor(), nullptr);
}

TEST(SolverRegistry, EveryRowRunsThePaperScenesFirstContact) {
  // Each row's factory builds its method, and the run reaches the first
  // touch (1.113 s) with the scene saying which integrator ran.
  for (const core::SolverEntry& e : core::solver_registry()) {
    core::Scene s = test::paper_scene();
    s.solver.method = e.method;
    s.solver.integrator = e.integrator;
    s.solver.fixed_step_s = 1e-6;
    s.end_time_s = 1.2;
    core::Simulation sim(s);
    EXPECT_EQ(sim.scene().solver.integrator, e.integrator);
    test::Collect out;
    sim.advance_to(s.end_time_s, out);
    ASSERT_FALSE(sim.failure().has_value()) << sim.failure()->message;
    ASSERT_FALSE(out.events.empty()) << core::to_string(e.method) << " " << core::to_string(e.integrator);
    EXPECT_NEAR(out.events.front().t_s, 1.1129, 1e-3) << core::to_string(e.integrator);
    EXPECT_EQ(sim.stats().integrator_switches, 0) << "the paper scene's free flight is not stiff for dop853";
  }
  // auto resolved where the run starts, and reported by the scene it ran.
  core::Scene s = test::paper_scene();
  s.end_time_s = 0.1;
  EXPECT_EQ(core::Simulation(s).scene().solver.integrator, Integrator::kDop853);
  s.solver.rtol = 1e-3;
  EXPECT_EQ(core::Simulation(s).scene().solver.integrator, Integrator::kDopri5);
}

}  // namespace
}  // namespace rotor_rub
