// The penalty method on the Jeffcott rotor (the class template:
// penalty_method_impl.hpp), and the factory that picks the rotor's kind.
#include <stdexcept>

#include "penalty_method_impl.hpp"

namespace rotor_rub::core {

// Instantiated in penalty_method_flexible.cpp, not here.
extern template std::unique_ptr<ContactMethod> make_penalty_for_rotor<Integrator::kRosenbrock4, true>(const Scene&);
extern template std::unique_ptr<ContactMethod> make_penalty_for_rotor<Integrator::kDopri5, true>(const Scene&);

template <Integrator I>
std::unique_ptr<ContactMethod> make_penalty_method(const Scene& scene) {
  static_assert(I == Integrator::kRosenbrock4 || I == Integrator::kRk4 || I == Integrator::kDopri5);
  if (!scene.rotor.file.empty()) {
    if constexpr (I != Integrator::kRk4) {
      return make_penalty_for_rotor<I, true>(scene);
    } else {
      throw std::logic_error("make_penalty_method: a flexible rotor runs on rosenbrock4 and dopri5 (validate_scene)");
    }
  }
  return make_penalty_for_rotor<I, false>(scene);
}
template std::unique_ptr<ContactMethod> make_penalty_method<Integrator::kRosenbrock4>(const Scene&);
template std::unique_ptr<ContactMethod> make_penalty_method<Integrator::kDopri5>(const Scene&);
template std::unique_ptr<ContactMethod> make_penalty_method<Integrator::kRk4>(const Scene&);

}  // namespace rotor_rub::core
