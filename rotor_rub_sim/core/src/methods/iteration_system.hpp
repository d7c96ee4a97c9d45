// The iteration method's one system of equations: the station under the
// rotor's free loads and the contact force iterated at every evaluation
// (contact_force_solver.hpp), and the jerk of its Hermite dense output. What
// its class template (iteration_method_impl.hpp) integrates. Private to that
// header's units, as it is (an unnamed namespace).
#pragma once

#include <cmath>

#include "methods/contact_force_solver.hpp"
#include "rotor/rotor_model.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"
#include "run/cost_profiler.hpp"

namespace rotor_rub::core {
namespace {

template <int kStatorDof, bool kMotor, class Rotor>
struct IterationSystem {
  using L = FreeLayout<kStatorDof, kMotor, Rotor>;
  // The jerk for the Hermite dense output (DenseHighOrder): a difference
  // (the contact force is a root, its rate no closed form), end_derivatives.
  static constexpr bool kOwnEndDerivatives = true;
  const StationModel* model = nullptr;
  const Rotor* rotor = nullptr;
  const ContactForceSolver* solver = nullptr;
  SpeedSegment segment;
  bool engaged = false;
  FrictionMode mode;
  long* iterations = nullptr;
  double* rhs_time_s = nullptr;        // profiling only
  double* iteration_time_s = nullptr;  // profiling only

  ContactForces forces(const Kinematics& k, const DriveState& d, const ContactGeometry& g, const FreeLoads& free,
                       double t) const {
    if (!engaged) return {};
    ProfileScope scope(iteration_time_s);
    return solver->solve(k, d, g, free, mode, false, t, *iterations);
  }

  void operator()(const typename L::State& x, typename L::State& dxdt, double t) const { derivative(x, dxdt, t); }

  // The derivative and its rate along the solution at a step's end: the
  // central difference of the derivative along (dxdt, 1) over
  // kHermiteJerkStep_s, but from the step's side of a release. Engaged, the
  // force is clamped at zero where nothing needs to press (a kink): a
  // difference across it is the clamp's, not the step's, and would bend the
  // interpolant of a step that ends just before a lift-off into the stator
  // (PaperScene.IterationLocatesItsLiftOffs). Where the two points differ
  // in being pressed, the second-order one-sided difference into the step
  // is taken (one evaluation more): at a step's end the pressed side, also
  // where the end lies on the kink itself (a step redone to end on its
  // lift-off, whose own force may round to either side). At a step's start
  // with a lift-off less than kHermiteJerkStep_s ahead it is the released
  // side; that step is cut at the lift-off, shorter than 1 us, where the
  // jerk's weight (h^3) leaves nothing to see.
  int end_derivatives(const typename L::State& x, double t, StepEnd end, typename L::State& dxdt,
                      typename L::State& ddx) const {
    constexpr double h = kHermiteJerkStep_s;
    typename L::State before, after, far;
    derivative(x, dxdt, t);
    const bool pressed_before = derivative(x - h * dxdt, before, t - h) > 0.0;
    const bool pressed_after = derivative(x + h * dxdt, after, t + h) > 0.0;
    if (pressed_before == pressed_after) {
      ddx = (after - before) / (2.0 * h);
      return 3;
    }
    if (end == StepEnd::kEnd) {
      derivative(x - 2.0 * h * dxdt, far, t - 2.0 * h);
      ddx = (3.0 * dxdt - 4.0 * before + far) / (2.0 * h);
    } else {
      derivative(x + 2.0 * h * dxdt, far, t + 2.0 * h);
      ddx = (4.0 * after - far - 3.0 * dxdt) / (2.0 * h);
    }
    return 4;
  }

  // The derivative; returns the normal force [N] (0 free or released).
  double derivative(const typename L::State& x, typename L::State& dxdt, double t) const {
    ProfileScope scope(rhs_time_s);
    const Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
    const DriveState reference = segment.at(t);
    const DriveState d = model->drive_at(k, reference);
    const ContactGeometry g = model->contact_geometry(k, d);
    const FreeLoads free = derivative_loads<L>(*rotor, *model, k, d, x, dxdt);
    const ContactForces f = forces(k, d, g, free, t);
    const Accelerations a = model->accelerations(d, g, free, f.normal_N, f.tangential_N);
    // A motor's spin: the rotor's block takes its share of its acceleration.
    if constexpr (kMotor) rotor->add_spin_share(free.unbalance_dir, a.spin_rad_per_s2, dxdt.tail(modal_count<L>(x)));
    free_derivative<L>(*model, k, reference, a, dxdt);
    return f.normal_N;
  }
};

}  // namespace
}  // namespace rotor_rub::core
