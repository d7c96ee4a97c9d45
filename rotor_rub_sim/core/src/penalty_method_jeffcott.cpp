// The penalty method on the Jeffcott rotor (the class template:
// penalty_method_impl.hpp), and the factory that picks the rotor's kind.
#include "penalty_method_impl.hpp"

namespace rotor_rub::core {

template <Integrator I>
std::unique_ptr<ContactMethod> make_penalty_method(const Scene& scene) {
  static_assert(I == Integrator::kRosenbrock4 || I == Integrator::kRk4 || I == Integrator::kDopri5);
  if (!scene.rotor.file.empty()) return make_penalty_flexible<I>(scene);
  return make_penalty_for_rotor<I, JeffcottRotor>(scene);
}
template std::unique_ptr<ContactMethod> make_penalty_method<Integrator::kRosenbrock4>(const Scene&);
template std::unique_ptr<ContactMethod> make_penalty_method<Integrator::kDopri5>(const Scene&);
template std::unique_ptr<ContactMethod> make_penalty_method<Integrator::kRk4>(const Scene&);

}  // namespace rotor_rub::core
