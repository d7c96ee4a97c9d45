// The penalty method on a flexible rotor (the class template:
// penalty_method_impl.hpp).
#include <stdexcept>

#include "penalty_method_impl.hpp"

namespace rotor_rub::core {

std::unique_ptr<ContactMethod> make_penalty_flexible(Integrator integrator, const Scene& scene) {
  switch (integrator) {
    case Integrator::kRosenbrock4:
      return make_penalty_for_rotor<Integrator::kRosenbrock4, true>(scene);
    case Integrator::kDopri5:
      return make_penalty_for_rotor<Integrator::kDopri5, true>(scene);
    case Integrator::kRk4:
      return make_penalty_for_rotor<Integrator::kRk4, true>(scene);
    default:
      throw std::logic_error("make_penalty_flexible: the penalty method does not run a flexible rotor on " +
                             std::string(to_string(integrator)) + " (validate_scene)");
  }
}

}  // namespace rotor_rub::core
