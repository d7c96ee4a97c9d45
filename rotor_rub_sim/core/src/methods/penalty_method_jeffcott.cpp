// The penalty method on the Jeffcott rotor (the class template:
// penalty_method_impl.hpp), instantiated for each integrator the registry runs
// it on (a row without it fails to link).
#include "penalty_method_impl.hpp"

namespace rotor_rub::core {

template <Integrator I>
std::unique_ptr<ContactMethod> make_penalty_jeffcott(const Scene& scene) {
  static_assert(I == Integrator::kRosenbrock4 || I == Integrator::kRk4 || I == Integrator::kDopri5);
  return make_penalty_for_rotor<I, JeffcottRotor>(scene);
}
template std::unique_ptr<ContactMethod> make_penalty_jeffcott<Integrator::kRosenbrock4>(const Scene&);
template std::unique_ptr<ContactMethod> make_penalty_jeffcott<Integrator::kDopri5>(const Scene&);
template std::unique_ptr<ContactMethod> make_penalty_jeffcott<Integrator::kRk4>(const Scene&);

}  // namespace rotor_rub::core
