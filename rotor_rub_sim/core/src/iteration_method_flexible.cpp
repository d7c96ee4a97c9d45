// The iteration method on a flexible rotor (the class template:
// iteration_method_impl.hpp).
#include "iteration_method_impl.hpp"

namespace rotor_rub::core {
template std::unique_ptr<ContactMethod> make_iteration_for_rotor<Integrator::kDopri5, true>(const Scene&);
template std::unique_ptr<ContactMethod> make_iteration_for_rotor<Integrator::kDop853, true>(const Scene&);
}  // namespace rotor_rub::core
