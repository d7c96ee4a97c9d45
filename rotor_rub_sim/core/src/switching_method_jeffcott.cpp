// The switching method on the Jeffcott rotor (the class template:
// switching_method_impl.hpp), and the factory that picks the rotor's kind.
#include "switching_method_impl.hpp"

namespace rotor_rub::core {

// Instantiated in switching_method_flexible.cpp, not here.
extern template std::unique_ptr<ContactMethod> make_switching_for_rotor<Integrator::kDopri5, true>(const Scene&);
extern template std::unique_ptr<ContactMethod> make_switching_for_rotor<Integrator::kRkf78, true>(const Scene&);
extern template std::unique_ptr<ContactMethod> make_switching_for_rotor<Integrator::kDop853, true>(const Scene&);

template <Integrator I>
std::unique_ptr<ContactMethod> make_switching_method(const Scene& scene) {
  if (!scene.rotor.file.empty()) return make_switching_for_rotor<I, true>(scene);  // switching_method_flexible.cpp
  return make_switching_for_rotor<I, false>(scene);
}
template std::unique_ptr<ContactMethod> make_switching_method<Integrator::kDopri5>(const Scene&);
template std::unique_ptr<ContactMethod> make_switching_method<Integrator::kRkf78>(const Scene&);
template std::unique_ptr<ContactMethod> make_switching_method<Integrator::kDop853>(const Scene&);

}  // namespace rotor_rub::core
