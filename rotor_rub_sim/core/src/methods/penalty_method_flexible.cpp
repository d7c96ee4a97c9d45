// The penalty method on a flexible rotor (the class template:
// penalty_method_impl.hpp).
#include "penalty_method_impl.hpp"

namespace rotor_rub::core {

template <Integrator I>
std::unique_ptr<ContactMethod> make_penalty_flexible(const Scene& scene) {
  return make_penalty_for_rotor<I, FlexibleRotor>(scene);
}
template std::unique_ptr<ContactMethod> make_penalty_flexible<Integrator::kRosenbrock4>(const Scene&);
template std::unique_ptr<ContactMethod> make_penalty_flexible<Integrator::kDopri5>(const Scene&);
template std::unique_ptr<ContactMethod> make_penalty_flexible<Integrator::kRk4>(const Scene&);

}  // namespace rotor_rub::core
