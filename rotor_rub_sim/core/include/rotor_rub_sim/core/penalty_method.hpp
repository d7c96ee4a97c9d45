// Method I: the contact as a stiff spring k_c with a damper consistent with
// the restitution (contact_law.hpp), acting while delta > C. One set of
// equations, no events needed to integrate; touchdown and lift-off are located
// on the dense output for reporting only.
#pragma once

#include <memory>

#include "rotor_rub_sim/core/contact_method.hpp"
#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

std::unique_ptr<ContactMethod> make_penalty_method(const Scene& scene);

}  // namespace rotor_rub::core
