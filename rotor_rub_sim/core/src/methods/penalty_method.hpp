// Method I: the contact as a stiff spring k_c with a damper consistent with
// the restitution (contact_law.hpp), acting while delta > C and pushing.
// With an explicit integrator, no contact force out of contact, the clamped law
// in it: a touchdown is located and restarted at, a lift-off located for the
// report (penalty_system.hpp). With the
// implicit one, the law's smooth pieces are integrated one at a time and the
// kinks between them located and restarted at (penalty_law.hpp), the pressed
// piece in the contact's polar coordinates (penalty_system.hpp).
#pragma once

#include <memory>

#include "rotor_rub_sim/core/contact_method.hpp"
#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

/// The penalty method on integrator I for a scene of the Jeffcott rotor, and of
/// a flexible rotor, for the scene's stator and drive (the registry's
/// factories: solver_registry.cpp). Instantiated for the integrators the
/// registry offers with it (rosenbrock4, dopri5 and rk4); a registry row without its
/// instantiation fails to link.
template <Integrator I>
std::unique_ptr<ContactMethod> make_penalty_jeffcott(const Scene& scene);
/// See make_penalty_jeffcott.
template <Integrator I>
std::unique_ptr<ContactMethod> make_penalty_flexible(const Scene& scene);

}  // namespace rotor_rub::core
