// validate_scene (scene_keys.hpp): what the key table's ranges cannot say
// alone, the keys' combinations and a flexible rotor's file, each refusal a
// SceneError naming the key, the value and the accepted range.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "integrators/rk4_stability.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/solver_registry.hpp"
#include "scene_text.hpp"

namespace rotor_rub::core {
namespace {

// Under a motor drive, the flexible rotor's counterpart of the Jeffcott's
// Painleve bound (contact_law.hpp): with L = max_phi h^T M^-1 h the spin's
// effective inertia is at least J - L, the station's lever at most l =
// sqrt(L / m_st), and sliding friction cannot pull the contact shut while
// J - L > f l (R_r + l) m_st.
void validate_flexible_spin(const Scene& s, const FlexibleRotorModel& rotor) {
  const double lever_kg_m2 = rotor.max_spin_lever_kg_m2(), m_st = rotor.station_mass_kg();
  const double l = std::sqrt(lever_kg_m2 / m_st);
  const double bound =
      lever_kg_m2 + s.model.friction_coefficient * l * (station_parameters(s.model, rotor).rotor_radius_m + l) * m_st;
  if (!(s.model.rotor_polar_inertia_kg_m2 > bound)) {
    throw SceneError("scene key 'rotor_polar_inertia_kg_m2': value " +
                     format_double(s.model.rotor_polar_inertia_kg_m2) +
                     " is out of range; accepted with drive_model motor and a rotor_file: above max h^T M^-1 h + f l "
                     "(R_r + l) m_st = " +
                     format_double(bound) +
                     " (the unbalances' lever on the spin, docs/rotors.md; below it the spin's inertia could vanish "
                     "or friction pull the contact shut)");
  }
}

// A flexible rotor: the file itself, read and reduced as a run will, and
// what runs on it (the spin's inertia under a motor drive, RK4's step).
void validate_flexible_rotor(const Scene& s) {
  std::shared_ptr<const FlexibleRotorModel> rotor;
  try {
    rotor = flexible_rotor_of(s);
  } catch (const SceneError& e) {
    // A count or a node out of the file's range names its own key
    // ("KEY: value ...", load_flexible_rotor).
    throw SceneError("scene key '" + e.key() + "'" + std::string(e.what()).substr(e.key().size()), e.key());
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    // The file's own error names the item and its accepted range where it has one.
    const bool ranged = what.find("accepted") != std::string::npos;
    throw SceneError("scene key 'rotor_file': value '" + s.rotor.file + "' is not accepted: " + what +
                     (ranged ? "" : "; accepted: a rotor file with a rub_station (docs/rotors.md)"));
  }
  if (s.model.drive_model == DriveModel::kMotor) validate_flexible_spin(s, *rotor);
  if (s.solver.method == Method::kPenalty && effective_integrator(s) == Integrator::kRk4) {
    const double h_max = flexible_rk4_stable_step_s(*rotor, s.model, s.speed.max_speed_rad_per_s);
    if (s.solver.fixed_step_s > h_max) {
      throw SceneError("scene key 'fixed_step_s': value " + format_double(s.solver.fixed_step_s) +
                       " is out of range; accepted with rk4 on this rotor and contact (rotor_file, "
                       "rotor_planar_modes = " +
                       std::to_string(rotor->rotor().planar_modes) +
                       ", contact_stiffness_N_per_m = " + format_double(s.model.contact_stiffness_N_per_m) +
                       ", max_speed_rad_per_s = " + format_double(s.speed.max_speed_rad_per_s) + "): (0, " +
                       format_double(h_max) +
                       "], RK4's stability bound on the rotor in sustained contact (docs/rotors.md)");
    }
  }
}

}  // namespace

void validate_scene(const Scene& s) {
  // Which integrators each method runs on, and why: solver_registry.cpp.
  const Integrator integrator = effective_integrator(s);
  if (find_solver(s.solver.method, integrator) == nullptr) {
    std::vector<std::string> with;
    for (const Method m : kAllMethods) {
      if (find_solver(m, integrator) != nullptr) with.push_back("'" + std::string(to_string(m)) + "'");
    }
    std::string methods = with.size() == 1 ? "method " + with[0] : "methods ";
    for (std::size_t i = 0; with.size() > 1 && i < with.size(); ++i) {
      methods += (i == 0 ? "" : i + 1 == with.size() ? " and " : ", ") + with[i];
    }
    throw SceneError("scene key 'integrator': value '" + std::string(to_string(integrator)) + "' is accepted with " +
                     methods + " only; accepted for method '" + to_string(s.solver.method) + "': auto, " +
                     integrators_of(s.solver.method));
  }
  if (s.solver.method == Method::kPenalty && integrator == Integrator::kRk4 && rotor_kind(s) == RotorKind::kJeffcott) {
    const double h_max = rk4_stable_step_s(JeffcottModel(s.model));
    if (s.solver.fixed_step_s > h_max) {
      throw SceneError("scene key 'fixed_step_s': value " + format_double(s.solver.fixed_step_s) +
                       " is out of range; accepted with rk4 on this contact (contact_stiffness_N_per_m = " +
                       format_double(s.model.contact_stiffness_N_per_m) +
                       ", restitution = " + format_double(s.model.restitution) + "): (0, " + format_double(h_max) +
                       "], RK4's stability bound on the contact mode (docs/numerics.md)");
    }
  }
  {
    // The rotor starts centred in the casing: inside the bore only when the
    // stator's offset is less than the clearance.
    const double offset = std::hypot(s.model.stator_offset_x_m, s.model.stator_offset_y_m);
    if (!(offset < s.model.clearance_m)) {
      throw SceneError("scene keys 'stator_offset_x_m', 'stator_offset_y_m': offset " + format_double(offset) +
                       " m is out of range; accepted: below clearance_m = " + format_double(s.model.clearance_m) +
                       " m (the rotor starts centred, inside the bore)");
    }
  }
  if (s.model.drive_model == DriveModel::kMotor && rotor_kind(s) == RotorKind::kJeffcott) {
    // Painleve's paradox (contact_law.hpp): with the spin in the contact's
    // compliance, sliding friction must never pull the bodies together.
    const double bound = s.model.friction_coefficient * s.model.eccentricity_m *
                         (s.model.rotor_radius_m + s.model.eccentricity_m) * s.model.rotor_mass_kg;
    if (!(s.model.rotor_polar_inertia_kg_m2 > bound)) {
      throw SceneError("scene key 'rotor_polar_inertia_kg_m2': value " +
                       format_double(s.model.rotor_polar_inertia_kg_m2) +
                       " is out of range; accepted with drive_model "
                       "motor: above f e (R_r + e) m_r = " +
                       format_double(bound) + " (below it friction could pull the contact shut: Painleve's paradox)");
    }
  }
  if (rotor_kind(s) == RotorKind::kFlexible) validate_flexible_rotor(s);
  if (s.speed.initial_speed_rad_per_s > s.speed.max_speed_rad_per_s) {
    throw SceneError(
        "scene key 'initial_speed_rad_per_s': value " + format_double(s.speed.initial_speed_rad_per_s) +
        " is out of range; accepted: [0, max_speed_rad_per_s = " + format_double(s.speed.max_speed_rad_per_s) + "]");
  }
  if (s.speed.target_speed_rad_per_s > s.speed.max_speed_rad_per_s) {
    throw SceneError(
        "scene key 'target_speed_rad_per_s': value " + format_double(s.speed.target_speed_rad_per_s) +
        " is out of range; accepted: [0, max_speed_rad_per_s = " + format_double(s.speed.max_speed_rad_per_s) + "]");
  }
  if (s.model.contact_damping_N_s_per_m > 0.0 && s.model.restitution > 0.0) {
    throw SceneError("scene keys 'contact_damping_N_s_per_m' (" + format_double(s.model.contact_damping_N_s_per_m) +
                     ") and 'restitution' (" + format_double(s.model.restitution) +
                     ") both set the penalty contact's damper; accepted: one of them (the other 0)");
  }
  if (s.speed.acceleration_rad_per_s2 == 0.0 && s.speed.target_speed_rad_per_s != s.speed.initial_speed_rad_per_s) {
    throw SceneError("scene key 'acceleration_rad_per_s2': value 0 holds the speed, but target_speed_rad_per_s = " +
                     format_double(s.speed.target_speed_rad_per_s) +
                     " is not initial_speed_rad_per_s = " + format_double(s.speed.initial_speed_rad_per_s) +
                     "; accepted: (0, inf) for a ramp to the target, 0 with the two speeds equal");
  }
  if (s.solver.min_step_s >= s.solver.initial_step_s) {
    throw SceneError("scene key 'min_step_s': value " + format_double(s.solver.min_step_s) +
                     " is out of range; accepted: (0, initial_step_s = " + format_double(s.solver.initial_step_s) +
                     ")");
  }
}

}  // namespace rotor_rub::core
