// The CVODE contender's integrator (cvode_switching.cpp): owners of
// SUNDIALS' C handles, one CVODE integrator per regime with its dense output
// and counters, and CVODE's failures as exceptions. Private to that unit, as
// it is (an unnamed namespace).
#pragma once

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_config.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "cvode_switching.hpp"
#include "rotor_rub_sim/core/parameters.hpp"

// SUNContext arrived in 6.0; 7.0 replaced the error handler (CVodeSetErrHandlerFn).
static_assert(SUNDIALS_VERSION_MAJOR == 6, "written against the SUNDIALS 6 API (Debian 12: 6.4.1)");

namespace rotor_rub::tools {
namespace {

// A CVODE call that failed: its flag, named by CVODE, and CVODE's message.
class CvodeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "call: CV_FLAG_NAME (CVODE's last message)".
std::string describe_failure(const std::string& call, int flag, const std::string& message) {
  char* name = CVodeGetReturnFlagName(flag);  // malloc'd by CVODE
  std::string s = call + ": " + (name ? name : "flag " + std::to_string(flag));
  std::free(name);
  return message.empty() ? s : s + " (" + message + ")";
}

// ---- Owners of SUNDIALS' C handles ------------------------------------------

struct ContextOwner {
  SUNContext ctx = nullptr;
  ContextOwner() {
    if (SUNContext_Create(nullptr, &ctx) != 0) throw CvodeError("SUNContext_Create failed");
  }
  ~ContextOwner() { SUNContext_Free(&ctx); }
  ContextOwner(const ContextOwner&) = delete;
  ContextOwner& operator=(const ContextOwner&) = delete;
};

struct VectorFree {
  void operator()(N_Vector v) const { N_VDestroy(v); }
};
struct MatrixFree {
  void operator()(SUNMatrix a) const { SUNMatDestroy(a); }
};
struct LinearSolverFree {
  void operator()(SUNLinearSolver s) const { SUNLinSolFree(s); }
};
struct NonlinearSolverFree {
  void operator()(SUNNonlinearSolver s) const { SUNNonlinSolFree(s); }
};
struct CvodeFree {
  void operator()(void* mem) const { CVodeFree(&mem); }
};
using VectorPtr = std::unique_ptr<std::remove_pointer_t<N_Vector>, VectorFree>;
using MatrixPtr = std::unique_ptr<std::remove_pointer_t<SUNMatrix>, MatrixFree>;
using LinearSolverPtr = std::unique_ptr<std::remove_pointer_t<SUNLinearSolver>, LinearSolverFree>;
using NonlinearSolverPtr = std::unique_ptr<std::remove_pointer_t<SUNNonlinearSolver>, NonlinearSolverFree>;
using CvodePtr = std::unique_ptr<void, CvodeFree>;

// CVODE reports errors through this instead of printing them: the run names
// the last one in its failure. Warnings (t + h == t) are dropped; a step that
// collapses ends in an error anyway.
void keep_error(int error_code, const char* /*module*/, const char* function, char* msg, void* data) {
  if (error_code == CV_WARNING) return;
  *static_cast<std::string*>(data) = std::string(function) + ": " + msg;
}

// ---- One CVODE integrator per regime ----------------------------------------

// Root functions, each an event when it rises through 0.
// Free flight: kGap = delta - C, and kForcedGap = delta - C - (atol + the
// flight's start penetration): the core's remedy for the stall (a flight that
// starts at a tangency and never opens the gap is contact once it penetrates
// by atol). When the gap has been open, kGap fires first.
// Contact: kLiftoff = -F_n; kFriction = -s v_slide (slip: the sliding stops)
// or |F_t,stick| - f F_n (stick: the stick force leaves the cone).
enum RootIndex { kGap = 0, kForcedGap = 1, kLiftoff = 0, kFriction = 1, kRoots = 2 };

// The two regimes' states differ in size (free: rotor and stator; contact:
// stator and contact angle), so each has its own CVODE memory, created once
// per run. A switch is then a CVodeReInit of the memory it enters: that keeps
// every vector, the nonlinear (and linear) solver and the root functions,
// where re-creating would allocate some 25 vectors and the solvers at every
// event for nothing in exchange.
class Integrator {
 public:
  Integrator(SUNContext ctx, int size, CVRhsFn rhs, CVRootFn roots, void* user_data, const core::Scene& scene,
             const CvodeOptions& options, std::string* error)
      : y_(N_VNew_Serial(size, ctx)), scratch_(N_VNew_Serial(size, ctx)), adams_(options.adams), error_(error) {
    if (!y_ || !scratch_) throw CvodeError("N_VNew_Serial failed");
    N_VConst(0.0, y_.get());
    // Fused vector operations: CVODE's predictor and corrector updates then
    // make one call per linear combination instead of one per term (the
    // vectors hold 2 to 8 numbers: the calls are the cost, not the loops).
    N_VEnableFusedOps_Serial(y_.get(), SUNTRUE);
    mem_.reset(CVodeCreate(adams_ ? CV_ADAMS : CV_BDF, ctx));
    if (!mem_) throw CvodeError("CVodeCreate failed");
    check(CVodeSetErrHandlerFn(mem(), keep_error, error_), "CVodeSetErrHandlerFn");
    check(CVodeInit(mem(), rhs, 0.0, y_.get()), "CVodeInit");
    check(CVodeSetUserData(mem(), user_data), "CVodeSetUserData");
    check(CVodeSStolerances(mem(), scene.solver.rtol, scene.solver.atol), "CVodeSStolerances");
    // CVODE's default of 500 steps per call to CVode would stop a run that
    // used CV_NORMAL; the run's own budget is scene.solver.max_steps.
    check(CVodeSetMaxNumSteps(mem(), scene.solver.max_steps), "CVodeSetMaxNumSteps");
    attach_solver(ctx, size);
    check(CVodeRootInit(mem(), kRoots, roots), "CVodeRootInit");
    std::array<int, kRoots> rising{1, 1};  // every event function is an event when it rises through 0
    check(CVodeSetRootDirection(mem(), rising.data()), "CVodeSetRootDirection");
    check(CVodeSetNoInactiveRootWarn(mem()), "CVodeSetNoInactiveRootWarn");
  }

  void* mem() const { return mem_.get(); }
  N_Vector y() const { return y_.get(); }
  double* state() const { return N_VGetArrayPointer(y_.get()); }

  // Restarts from state() at t_s (order 1: the history is not that of the
  // new problem), up to stop_s, trying initial_step_s first (0: CVODE's own
  // estimate). CVODE 6.4.1 forgets a stop time once it has stopped there:
  // set at every restart.
  void reinit(double t_s, double stop_s, double initial_step_s, CvodeRun& out) {
    harvest(out);
    check(CVodeSetInitStep(mem(), initial_step_s), "CVodeSetInitStep");
    check(CVodeReInit(mem(), t_s, y_.get()), "CVodeReInit");
    set_stop(stop_s);
    ++out.reinits;
  }
  void set_stop(double stop_s) { check(CVodeSetStopTime(mem(), stop_s), "CVodeSetStopTime"); }
  // The step CVODE would try next (after its last step's adjustment).
  double next_step_s() const {
    double h = 0.0;
    check(CVodeGetCurrentStep(mem(), &h), "CVodeGetCurrentStep");
    return h;
  }

  // The dense output at t (inside the last step) into a scratch vector.
  const double* state_at(double t_s) {
    check(CVodeGetDky(mem(), t_s, 0, scratch_.get()), "CVodeGetDky");
    return N_VGetArrayPointer(scratch_.get());
  }

  // Adds the counters since the last (re)initialisation to out: CVodeReInit
  // sets them back to zero. The linear solver's (BDF) are reset later, by
  // the first CVode call after it (measured on 6.4.1): read only when steps
  // were taken since, else they would count the previous interval twice.
  void harvest(CvodeRun& out) const {
    long steps = 0, v = 0;
    check(CVodeGetNumSteps(mem(), &steps), "CVodeGetNumSteps");
    out.steps += steps;
    check(CVodeGetNumRhsEvals(mem(), &v), "CVodeGetNumRhsEvals");
    out.rhs_evals += v;
    if (!adams_ && steps > 0) {
      check(CVodeGetNumLinRhsEvals(mem(), &v), "CVodeGetNumLinRhsEvals");
      out.rhs_evals += v;
    }
    check(CVodeGetNumGEvals(mem(), &v), "CVodeGetNumGEvals");
    out.root_evals += v;
    check(CVodeGetNumErrTestFails(mem(), &v), "CVodeGetNumErrTestFails");
    out.error_test_failures += v;
    check(CVodeGetNumStepSolveFails(mem(), &v), "CVodeGetNumStepSolveFails");
    out.nonlinear_failures += v;
  }

  void check(int flag, const char* call) const {
    if (flag < 0) throw CvodeError(describe_failure(call, flag, *error_));
  }

 private:
  void attach_solver(SUNContext ctx, int size) {
    if (adams_) {
      // Non-stiff: the corrector by fixed-point iteration, no Jacobian.
      nls_.reset(SUNNonlinSol_FixedPoint(y_.get(), 0, ctx));
      if (!nls_) throw CvodeError("SUNNonlinSol_FixedPoint failed");
      check(CVodeSetNonlinearSolver(mem(), nls_.get()), "CVodeSetNonlinearSolver");
      return;
    }
    // BDF: CVODE's default Newton iteration on a dense Jacobian by difference
    // quotients (size RHS evaluations each, counted in rhs_evals).
    matrix_.reset(SUNDenseMatrix(size, size, ctx));
    linear_solver_.reset(SUNLinSol_Dense(y_.get(), matrix_.get(), ctx));
    if (!matrix_ || !linear_solver_) throw CvodeError("SUNDenseMatrix/SUNLinSol_Dense failed");
    check(CVodeSetLinearSolver(mem(), linear_solver_.get(), matrix_.get()), "CVodeSetLinearSolver");
  }

  // Members are destroyed in reverse: the CVODE memory first, then the
  // solvers and vectors it uses (CVodeFree frees neither).
  VectorPtr y_, scratch_;
  MatrixPtr matrix_;
  LinearSolverPtr linear_solver_;
  NonlinearSolverPtr nls_;
  CvodePtr mem_;
  bool adams_;
  std::string* error_;
};

}  // namespace
}  // namespace rotor_rub::tools
