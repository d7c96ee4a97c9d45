// The iteration method on the Jeffcott rotor (the class template:
// iteration_method_impl.hpp), and the factory that picks the rotor's kind.
#include "iteration_method_impl.hpp"

namespace rotor_rub::core {

// Instantiated in iteration_method_flexible.cpp, not here.
extern template std::unique_ptr<ContactMethod> make_iteration_for_rotor<Integrator::kDopri5, true>(const Scene&);
extern template std::unique_ptr<ContactMethod> make_iteration_for_rotor<Integrator::kDop853, true>(const Scene&);

template <Integrator I>
std::unique_ptr<ContactMethod> make_iteration_method(const Scene& scene) {
  if (!scene.rotor.file.empty()) return make_iteration_for_rotor<I, true>(scene);
  return make_iteration_for_rotor<I, false>(scene);
}
template std::unique_ptr<ContactMethod> make_iteration_method<Integrator::kDopri5>(const Scene&);
template std::unique_ptr<ContactMethod> make_iteration_method<Integrator::kDop853>(const Scene&);

}  // namespace rotor_rub::core
