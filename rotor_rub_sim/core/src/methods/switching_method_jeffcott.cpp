// The switching method on the Jeffcott rotor (the class template:
// switching_method_impl.hpp), instantiated for each integrator the registry runs
// it on (a row without it fails to link).
#include "switching_method_impl.hpp"

namespace rotor_rub::core {

template <Integrator I>
std::unique_ptr<ContactMethod> make_switching_jeffcott(const Scene& scene) {
  return make_switching_for_rotor<I, JeffcottRotor>(scene);
}
template std::unique_ptr<ContactMethod> make_switching_jeffcott<Integrator::kDopri5>(const Scene&);
template std::unique_ptr<ContactMethod> make_switching_jeffcott<Integrator::kRkf78>(const Scene&);
template std::unique_ptr<ContactMethod> make_switching_jeffcott<Integrator::kDop853>(const Scene&);
template std::unique_ptr<ContactMethod> make_switching_jeffcott<Integrator::kRosenbrock4>(const Scene&);
template std::unique_ptr<ContactMethod> make_switching_jeffcott<Integrator::kDop853Rosenbrock4>(const Scene&);

}  // namespace rotor_rub::core
