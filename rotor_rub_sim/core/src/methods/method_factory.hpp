// A contact method instantiated for a scene's stator (elastic: 2 DOF, rigid:
// 0) and drive (a motor adds the spin's states): the four cases in one place.
#pragma once

#include <memory>

#include "rotor_rub_sim/core/contact_method.hpp"
#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

template <template <int, bool> class Method>
std::unique_ptr<ContactMethod> make_for_scene(const Scene& scene) {
  const bool rigid = scene.model.stator_model == StatorModel::kRigid;
  if (scene.model.drive_model == DriveModel::kMotor) {
    if (rigid) return std::make_unique<Method<0, true>>(scene);
    return std::make_unique<Method<2, true>>(scene);
  }
  if (rigid) return std::make_unique<Method<0, false>>(scene);
  return std::make_unique<Method<2, false>>(scene);
}

}  // namespace rotor_rub::core
