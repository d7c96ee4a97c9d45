// The switching method on the Jeffcott rotor (the class template:
// switching_method_impl.hpp), and the factory that picks the rotor's kind.
#include "switching_method_impl.hpp"

namespace rotor_rub::core {

template <Integrator I>
std::unique_ptr<ContactMethod> make_switching_method(const Scene& scene) {
  if (!scene.rotor.file.empty()) return make_switching_flexible<I>(scene);
  return make_switching_for_rotor<I, JeffcottRotor>(scene);
}
template std::unique_ptr<ContactMethod> make_switching_method<Integrator::kDopri5>(const Scene&);
template std::unique_ptr<ContactMethod> make_switching_method<Integrator::kRkf78>(const Scene&);
template std::unique_ptr<ContactMethod> make_switching_method<Integrator::kDop853>(const Scene&);

}  // namespace rotor_rub::core
