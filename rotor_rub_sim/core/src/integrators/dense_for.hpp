// The dense-output integrator of an integrator key on a layout L (its state
// L::State), for the rigid methods' regimes (switching_systems.hpp,
// iteration_system.hpp), and the explicit scheme that takes a regime whose
// system has no Jacobian in closed form where the key names the implicit one.
#pragma once

#include <type_traits>

#include "integrators/dense_dopri5.hpp"
#include "integrators/dense_high_order.hpp"
#include "integrators/dense_rodasp.hpp"
#include "integrators/dense_stiffness_switch.hpp"
#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

template <class L, Integrator I>
using DenseFor = std::conditional_t<
    I == Integrator::kDop853, DenseDop853<L>,
    std::conditional_t<
        I == Integrator::kRkf78, DenseRkf78<L>,
        std::conditional_t<
            I == Integrator::kRosenbrock4, DenseRodasp<typename L::State>,
            std::conditional_t<I == Integrator::kDop853Rosenbrock4, DenseStiffnessSwitch<L>,
                               std::conditional_t<I == Integrator::kDopri5, DenseDopri5<typename L::State>, void>>>>>;

// rosenbrock4 (RODASP) runs free flight only, dop853 the regime in contact
// (the constrained dynamics and the iterated force have no Jacobian in closed
// form), as dop853_rosenbrock4 does where its free flight is on RODASP; every
// other key runs both.
constexpr Integrator explicit_partner(Integrator i) {
  return i == Integrator::kRosenbrock4 || i == Integrator::kDop853Rosenbrock4 ? Integrator::kDop853 : i;
}

// The scheme of a regime integrator's last step, and of its next step or
// restart: the key's own, but dop853_rosenbrock4's engine (DenseStiffnessSwitch).
template <Integrator I, class Dense>
Integrator scheme_now(const Dense& dense) {
  if constexpr (I == Integrator::kDop853Rosenbrock4) {
    return dense.scheme_now();
  } else {
    return I;
  }
}
template <Integrator I, class Dense>
Integrator scheme_next(const Dense& dense) {
  if constexpr (I == Integrator::kDop853Rosenbrock4) {
    return dense.scheme_next();
  } else {
    return I;
  }
}

}  // namespace rotor_rub::core
