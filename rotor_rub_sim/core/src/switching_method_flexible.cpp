// The switching method on a flexible rotor (the class template:
// switching_method_impl.hpp).
#include <stdexcept>

#include "switching_method_impl.hpp"

namespace rotor_rub::core {

std::unique_ptr<ContactMethod> make_switching_flexible(Integrator integrator, const Scene& scene) {
  switch (integrator) {
    case Integrator::kDopri5:
      return make_switching_for_rotor<Integrator::kDopri5, true>(scene);
    case Integrator::kRkf78:
      return make_switching_for_rotor<Integrator::kRkf78, true>(scene);
    case Integrator::kDop853:
      return make_switching_for_rotor<Integrator::kDop853, true>(scene);
    default:
      throw std::logic_error("make_switching_flexible: the switching method does not run a flexible rotor on " +
                             std::string(to_string(integrator)) + " (validate_scene)");
  }
}

}  // namespace rotor_rub::core
