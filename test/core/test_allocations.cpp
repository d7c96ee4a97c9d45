// No allocation per step: every method on every integrator it offers, on the
// Jeffcott and on a flexible rotor, advances a run in contact and out of it
// without a heap allocation once warmed up (the state, the integrators' stages
// and the reduced rotor's work vectors are sized at the start). Its own
// binary: it replaces malloc, calloc and realloc with counting wrappers
// around glibc's, which every allocation (operator new, Eigen's) goes
// through.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>

#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "rotor_rub_sim/core/solver_registry.hpp"

extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
}

namespace {
bool counting = false;
long allocations = 0;
}  // namespace

extern "C" {
void* malloc(std::size_t size) {
  if (counting) ++allocations;
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) {
  if (counting) ++allocations;
  return __libc_calloc(count, size);
}
void* realloc(void* p, std::size_t size) {
  if (counting) ++allocations;
  return __libc_realloc(p, size);
}
}

using namespace rotor_rub;

namespace {

// Samples, events and keyphasors delivered and dropped: the observer's own
// storage is the caller's business, not the step's.
struct Discard : core::SimulationObserver {};

std::string source(const std::string& rel) { return std::string(ROTOR_RUB_SOURCE_DIR) + "/" + rel; }

// Allocations while the run advances from t0 to t1 (after advancing to t0).
long allocations_between(const core::Scene& scene, double t0_s, double t1_s) {
  core::Simulation sim(scene);
  Discard observer;
  EXPECT_TRUE(sim.advance_to(t0_s, observer)) << sim.failure()->message;
  allocations = 0;
  counting = true;
  const bool ok = sim.advance_to(t1_s, observer);
  counting = false;
  EXPECT_TRUE(ok) << sim.failure()->message;
  return allocations;
}

}  // namespace

// The paper's run-up in contact (first contact 1.11 s) and the seal-rub
// run-up of a flexible rotor at 8 planar modes and at its full FE model (26)
// across its first contact (1.24 s), and at 8 with an elastic stator and
// under a motor drive (the penalty method's polar coordinates with the block
// beside them, its Jacobian in closed form or differenced): every registry
// row. A rotor of 73 nodes at its full model (146 planar modes, more than
// 128: the storage's size is not the method's business) in free flight on
// rosenbrock4, the integrator such a model runs on (test_large_rotor).
TEST(Allocations, NoneWhileARunAdvances) {
  struct Case {
    const char* scene;
    long planar_modes;  // 0: the scene's rotor
    double t0_s, t1_s;
    bool elastic_stator = false, motor = false;
    const char* rotor_file = nullptr;  // the scene's own unless named
  };
  for (const Case& c : {Case{"config/paper_runup.yaml", 0, 1.0, 1.3}, Case{"config/seal_rub_runup.yaml", 8, 1.2, 1.3},
                        Case{"config/seal_rub_runup.yaml", 26, 1.23, 1.25},
                        Case{"config/seal_rub_runup.yaml", 8, 1.2, 1.3, true, false},
                        Case{"config/seal_rub_runup.yaml", 8, 1.2, 1.3, false, true},
                        Case{"config/seal_rub_runup.yaml", 146, 0.001, 0.0015, false, false,
                             "test/data/rotors/fine_damped_seal.yaml"}}) {
    for (const core::SolverEntry& row : core::solver_registry()) {
      if (row.integrator == core::Integrator::kRk4) continue;  // its fixed step: test_flexible_rk4
      if (c.rotor_file && row.integrator != core::Integrator::kRosenbrock4) continue;
      core::Scene scene = core::load_scene(source(c.scene));
      if (c.rotor_file) scene.rotor.file = source(c.rotor_file);
      scene.solver.method = row.method;
      scene.solver.integrator = row.integrator;
      if (c.planar_modes > 0) scene.rotor.planar_modes = c.planar_modes;
      if (c.elastic_stator) scene.model.stator_model = core::StatorModel::kElastic;
      if (c.motor) {
        // A motor strong enough to hold the run-up through the rub.
        scene.model.drive_model = core::DriveModel::kMotor;
        scene.model.drive_torque_limit_N_m = 200.0;
      }
      EXPECT_EQ(allocations_between(scene, c.t0_s, c.t1_s), 0)
          << c.scene << " " << c.planar_modes << " planar modes" << (c.elastic_stator ? ", elastic stator" : "")
          << (c.motor ? ", motor" : "") << ", " << core::to_string(row.method) << " on "
          << core::to_string(row.integrator);
    }
  }
}
