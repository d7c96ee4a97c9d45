// The switching method on a flexible rotor (the class template:
// switching_method_impl.hpp).
#include "switching_method_impl.hpp"

namespace rotor_rub::core {

template <Integrator I>
std::unique_ptr<ContactMethod> make_switching_flexible(const Scene& scene) {
  return make_switching_for_rotor<I, FlexibleRotor>(scene);
}
template std::unique_ptr<ContactMethod> make_switching_flexible<Integrator::kDopri5>(const Scene&);
template std::unique_ptr<ContactMethod> make_switching_flexible<Integrator::kRkf78>(const Scene&);
template std::unique_ptr<ContactMethod> make_switching_flexible<Integrator::kDop853>(const Scene&);
template std::unique_ptr<ContactMethod> make_switching_flexible<Integrator::kRosenbrock4>(const Scene&);
template std::unique_ptr<ContactMethod> make_switching_flexible<Integrator::kDop853Rosenbrock4>(const Scene&);

}  // namespace rotor_rub::core
