// The dense-output integrator of an integrator key on a layout L (its state
// L::State), for the rigid methods' regimes (switching_systems.hpp,
// iteration_system.hpp), and the explicit scheme that takes a regime whose
// system has no Jacobian in closed form where the key names the implicit one.
#pragma once

#include <type_traits>

#include "integrators/dense_dopri5.hpp"
#include "integrators/dense_high_order.hpp"
#include "integrators/dense_rodasp.hpp"
#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

template <class L, Integrator I>
using DenseFor = std::conditional_t<
    I == Integrator::kDop853, DenseDop853<L>,
    std::conditional_t<
        I == Integrator::kRkf78, DenseRkf78<L>,
        std::conditional_t<I == Integrator::kRosenbrock4, DenseRodasp<typename L::State>,
                           std::conditional_t<I == Integrator::kDopri5, DenseDopri5<typename L::State>, void>>>>;

// rosenbrock4 (RODASP) runs free flight only, dop853 the regime in contact
// (the constrained dynamics and the iterated force have no Jacobian in closed
// form); every other key runs both.
constexpr Integrator explicit_partner(Integrator i) { return i == Integrator::kRosenbrock4 ? Integrator::kDop853 : i; }

}  // namespace rotor_rub::core
