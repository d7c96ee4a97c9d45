#include "rotor_rub_sim/core/parameters.hpp"

#include <stdexcept>

namespace rotor_rub::core {

// No default labels: -Wswitch names a value added without a name. The
// return after each switch is for a value cast from an integer out of range.
const char* to_string(Method m) {
  switch (m) {
    case Method::kPenalty:
      return "penalty";  // paper method I
    case Method::kSwitching:
      return "switching";  // paper method II
    case Method::kIteration:
      return "iteration";  // paper method III
  }
  throw std::logic_error("to_string: not a Method");
}

const char* to_string(RotorKind r) {
  switch (r) {
    case RotorKind::kJeffcott:
      return "jeffcott";
    case RotorKind::kFlexible:
      return "flexible";
  }
  throw std::logic_error("to_string: not a RotorKind");
}

const char* to_string(Integrator i) {
  switch (i) {
    case Integrator::kAuto:
      return "auto";  // the registry's choice for the method
    case Integrator::kDopri5:
      return "dopri5";  // explicit embedded RK 5(4), ode45's scheme
    case Integrator::kRosenbrock4:
      return "rosenbrock4";  // RODASP, linearly implicit 4(3), stiff
    case Integrator::kRk4:
      return "rk4";  // classic RK4, fixed step fixed_step_s
    case Integrator::kRkf78:
      return "rkf78";  // explicit embedded RK 7(8), Hermite dense output
    case Integrator::kDop853:
      return "dop853";  // explicit embedded RK 8(5,3), Hermite dense output
    case Integrator::kDop853Rosenbrock4:
      return "dop853_rosenbrock4";  // dop853, RODASP in free flight where dop853's steps are bound by stability
  }
  throw std::logic_error("to_string: not an Integrator");
}

const char* to_string(StatorModel s) {
  switch (s) {
    case StatorModel::kElastic:
      return "elastic";  // stator on springs: 4 DOF in all
    case StatorModel::kRigid:
      return "rigid";  // immovable stator: the rotor's 2 DOF only
  }
  throw std::logic_error("to_string: not a StatorModel");
}

const char* to_string(DriveModel d) {
  switch (d) {
    case DriveModel::kPrescribed:
      return "prescribed";  // the speed profile is the spin (the paper's kinematic drive)
    case DriveModel::kMotor:
      return "motor";  // the spin a state: a speed-controlled motor against the rub's torque
  }
  throw std::logic_error("to_string: not a DriveModel");
}

Method method_from_string(const std::string& s) { return value_named(kAllMethods, s, "method"); }
Integrator integrator_from_string(const std::string& s) { return value_named(kAllIntegrators, s, "integrator"); }
StatorModel stator_model_from_string(const std::string& s) { return value_named(kAllStatorModels, s, "stator_model"); }
DriveModel drive_model_from_string(const std::string& s) { return value_named(kAllDriveModels, s, "drive_model"); }

}  // namespace rotor_rub::core
