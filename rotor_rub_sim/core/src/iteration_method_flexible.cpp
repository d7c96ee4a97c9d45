// The iteration method on a flexible rotor (the class template:
// iteration_method_impl.hpp).
#include <stdexcept>

#include "iteration_method_impl.hpp"

namespace rotor_rub::core {

std::unique_ptr<ContactMethod> make_iteration_flexible(Integrator integrator, const Scene& scene) {
  switch (integrator) {
    case Integrator::kDopri5:
      return make_iteration_for_rotor<Integrator::kDopri5, true>(scene);
    case Integrator::kDop853:
      return make_iteration_for_rotor<Integrator::kDop853, true>(scene);
    default:
      throw std::logic_error("make_iteration_flexible: the iteration method does not run a flexible rotor on " +
                             std::string(to_string(integrator)) + " (validate_scene)");
  }
}

}  // namespace rotor_rub::core
