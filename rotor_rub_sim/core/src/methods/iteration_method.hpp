// Method III: one set of equations (the free state); the normal force is found
// by a bracketing root finder (TOMS 748) wherever the rotor is held at the
// bore, so that it stays within the stator.
//
// Design (why not the paper's literal scheme): a force held constant over a
// step and iterated until the gap closes at the step's end turns the closing
// normal velocity v into -v at every step (the position condition fixes
// v h + a h^2 / 2 = 0), so the force alternates in sign from step to step,
// and its error is tied to the step size rather than to the tolerance.
// Instead:
// * While engaged, every right-hand-side evaluation finds the F_n >= 0 that
//   makes the distance's acceleration delta'' vanish, by TOMS 748 on the
//   model's own accelerations (the model is a black box to the root finder,
//   as a large FE model would be). The force is then consistent with the
//   constraint at every stage, smooth within a step, and the integrator's
//   error control covers it. If F_n = 0 already gives delta'' <= 0 the force
//   is released (0).
// * After every engaged step the drift of delta from C and of delta' from 0
//   (of the order of the local error) is projected out, mass-weighted.
// * Touchdown without event location: a free step that reaches more than
//   atol beyond the clearance anywhere on its dense output (the scan's
//   points, and a graze's located maximum inside the step) is rejected and
//   retried with half the step, until it ends within [-atol, atol] of the
//   bore; there the impact law applies and the contact engages if F_n > 0.
//   The rotor thus stays within the stator to atol, and the touchdown time
//   is resolved to about atol / v_closing.
// * Lift-off is located inside an engaged step, on its dense output, where
//   the pressing on the bore falls through zero (locate_liftoff); the free
//   flight restarts there from the state placed on the bore. A step that was
//   not pressed at its start is decided at its end, when F_n = 0 already
//   separates. Stick/slip transitions are located inside a step too.
#pragma once

#include <memory>

#include "rotor_rub_sim/core/contact_method.hpp"
#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

/// The iteration method on integrator I for a scene of the Jeffcott rotor, and of
/// a flexible rotor, for the scene's stator and drive (the registry's
/// factories: solver_registry.cpp). Instantiated for the integrators the
/// registry offers with it (dopri5, dop853, rosenbrock4); a registry row without its
/// instantiation fails to link.
template <Integrator I>
std::unique_ptr<ContactMethod> make_iteration_jeffcott(const Scene& scene);
/// See make_iteration_jeffcott.
template <Integrator I>
std::unique_ptr<ContactMethod> make_iteration_flexible(const Scene& scene);

}  // namespace rotor_rub::core
