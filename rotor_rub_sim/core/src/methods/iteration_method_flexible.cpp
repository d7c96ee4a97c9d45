// The iteration method on a flexible rotor (the class template:
// iteration_method_impl.hpp).
#include "iteration_method_impl.hpp"

namespace rotor_rub::core {

template <Integrator I>
std::unique_ptr<ContactMethod> make_iteration_flexible(const Scene& scene) {
  return make_iteration_for_rotor<I, FlexibleRotor>(scene);
}
template std::unique_ptr<ContactMethod> make_iteration_flexible<Integrator::kDopri5>(const Scene&);
template std::unique_ptr<ContactMethod> make_iteration_flexible<Integrator::kDop853>(const Scene&);
template std::unique_ptr<ContactMethod> make_iteration_flexible<Integrator::kRosenbrock4>(const Scene&);
template std::unique_ptr<ContactMethod> make_iteration_flexible<Integrator::kDop853Rosenbrock4>(const Scene&);

}  // namespace rotor_rub::core
