// The iteration method on the Jeffcott rotor (the class template:
// iteration_method_impl.hpp), and the factory that picks the rotor's kind.
#include "iteration_method_impl.hpp"

namespace rotor_rub::core {

template <Integrator I>
std::unique_ptr<ContactMethod> make_iteration_method(const Scene& scene) {
  if (!scene.rotor.file.empty()) return make_iteration_flexible<I>(scene);
  return make_iteration_for_rotor<I, JeffcottRotor>(scene);
}
template std::unique_ptr<ContactMethod> make_iteration_method<Integrator::kDopri5>(const Scene&);
template std::unique_ptr<ContactMethod> make_iteration_method<Integrator::kDop853>(const Scene&);

}  // namespace rotor_rub::core
