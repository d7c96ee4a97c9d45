// The penalty method on a flexible rotor (the class template:
// penalty_method_impl.hpp): rosenbrock4 and dopri5 (solver_registry.cpp).
#include "penalty_method_impl.hpp"

namespace rotor_rub::core {
template std::unique_ptr<ContactMethod> make_penalty_for_rotor<Integrator::kRosenbrock4, true>(const Scene&);
template std::unique_ptr<ContactMethod> make_penalty_for_rotor<Integrator::kDopri5, true>(const Scene&);
}  // namespace rotor_rub::core
