// Method II: two sets of equations, switched by event location.
//
// * Free flight: the free state (rotor, stator), no contact force.
// * Contact: reduced coordinates that hold the constraint |r_r - r_s| = C
//   exactly: the stator's position and the contact angle psi, with
//   r_r = r_s + C (cos psi, sin psi). The normal force is the constraint
//   force, in closed form (switching_method_impl.hpp). Drift of the constraint is
//   impossible by construction, so loose tolerances give no false lift-offs.
// * Touchdown: delta - C crosses 0 upward (located on the dense output); the
//   impact law (contact_law.hpp) is applied; contact follows if it settles and
//   the constraint force is positive, else the event is a graze.
// * Lift-off: the constraint force crosses 0 downward.
// * Chatter guard (the paper's stall): right after a switch the new regime's
//   event function starts at its switching surface. An event is recognised
//   only after the event function has been seen strictly on its own side
//   (armed); if a free flight that never opened the gap penetrates beyond
//   atol, contact is forced (the paper's "enter the next regime at least
//   once"). Too many events per simulated millisecond fail the run (stalled).
#pragma once

#include <memory>

#include "rotor_rub_sim/core/contact_method.hpp"
#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

/// The switching method on integrator I for a scene of the Jeffcott rotor, and of
/// a flexible rotor, for the scene's stator and drive (the registry's
/// factories: solver_registry.cpp). Instantiated for the integrators the
/// registry offers with it (dopri5, rkf78 and dop853); a registry row without its
/// instantiation fails to link.
template <Integrator I>
std::unique_ptr<ContactMethod> make_switching_jeffcott(const Scene& scene);
/// See make_switching_jeffcott.
template <Integrator I>
std::unique_ptr<ContactMethod> make_switching_flexible(const Scene& scene);

}  // namespace rotor_rub::core
