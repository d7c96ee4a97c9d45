#include "rotor_rub_sim/core/scene_keys.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <sstream>

#include "integrators/rk4_stability.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/solver_registry.hpp"
#include "scene_text.hpp"

namespace rotor_rub::core {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Strict number parsing: the whole text must be a finite number.
double parse_number(const std::string& key, const std::string& text, const std::string& accepted) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    throw SceneError("scene key '" + key + "': value '" + text + "' is not a number; accepted: " + accepted);
  }
  while (used < text.size() && std::isspace(static_cast<unsigned char>(text[used]))) ++used;
  if (used != text.size() || !std::isfinite(v)) {
    throw SceneError("scene key '" + key + "': value '" + text + "' is not a finite number; accepted: " + accepted);
  }
  return v;
}

struct KeyEntry {
  SceneKeyInfo info;
  std::function<void(Scene&, const std::string&)> set;
  // The text set() reads back to the same value (the scene by value: ref()
  // hands out a mutable reference).
  std::function<std::string(Scene)> get;
};

SceneKeyInfo key_info(std::string key, std::string accepted, std::string description, std::string default_value) {
  SceneKeyInfo i;
  i.key = std::move(key);
  i.accepted = std::move(accepted);
  i.description = std::move(description);
  i.default_value = std::move(default_value);
  return i;
}

// A real-valued key in [lo, hi] (lo exclusive when lo_open).
KeyEntry real(std::string key, double lo, bool lo_open, double hi, std::string description,
              std::function<double&(Scene&)> ref) {
  std::string accepted = std::string(lo_open ? "(" : "[") + format_double(lo) + ", " +
                         (std::isinf(hi) ? std::string("inf)") : format_double(hi) + "]");
  Scene defaults;
  std::string def = format_double(ref(defaults));
  KeyEntry e{key_info(key, accepted, std::move(description), def), nullptr,
             [ref](Scene s) { return exact_text(ref(s)); }};
  e.info.min_value = lo;
  e.info.max_value = hi;
  e.set = [key, lo, lo_open, hi, accepted, ref](Scene& s, const std::string& text) {
    const double v = parse_number(key, text, accepted);
    const bool below = lo_open ? !(v > lo) : !(v >= lo);
    if (below || v > hi) {
      throw SceneError("scene key '" + key + "': value " + text + " is out of range; accepted: " + accepted);
    }
    ref(s) = v;
  };
  return e;
}

KeyEntry integer(std::string key, long lo, long hi, std::string description, std::function<long&(Scene&)> ref) {
  std::string accepted = "integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  Scene defaults;
  KeyEntry e{key_info(key, accepted, std::move(description), std::to_string(ref(defaults))), nullptr,
             [ref](Scene s) { return std::to_string(ref(s)); }};
  e.info.min_value = static_cast<double>(lo);
  e.info.max_value = static_cast<double>(hi);
  e.info.is_integer = true;
  e.set = [key, lo, hi, accepted, ref](Scene& s, const std::string& text) {
    const double v = parse_number(key, text, accepted);
    if (std::isfinite(v) && v != std::floor(v)) {
      throw SceneError("scene key '" + key + "': value " + text + " is not an integer; accepted: " + accepted);
    }
    if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi))) {
      throw SceneError("scene key '" + key + "': value " + text + " is out of range; accepted: " + accepted);
    }
    ref(s) = static_cast<long>(v);
  };
  return e;
}

// An integer key in [lo, hi] that also takes `auto` (held as 0).
KeyEntry integer_or_auto(std::string key, long lo, long hi, std::string description, std::function<long&(Scene&)> ref) {
  KeyEntry e = integer(key, lo, hi, std::move(description), ref);
  e.info.accepted = "auto or " + e.info.accepted;
  Scene defaults;
  if (ref(defaults) == 0) e.info.default_value = "auto";
  e.set = [key, lo, hi, accepted = e.info.accepted, ref](Scene& s, const std::string& text) {
    if (text == "auto") {
      ref(s) = 0;
      return;
    }
    const double v = parse_number(key, text, accepted);
    if (v != std::floor(v) || !(v >= static_cast<double>(lo) && v <= static_cast<double>(hi))) {
      throw SceneError("scene key '" + key + "': value " + text + " is " +
                       (v != std::floor(v) ? "not an integer" : "out of range") + "; accepted: " + accepted);
    }
    ref(s) = static_cast<long>(v);
  };
  e.get = [ref](Scene s) { return ref(s) == 0 ? std::string("auto") : std::to_string(ref(s)); };
  return e;
}

// A text key (a file's path): any text; what it names is checked by
// validate_scene.
KeyEntry text(std::string key, std::string accepted, std::string description, std::function<std::string&(Scene&)> ref) {
  Scene defaults;
  KeyEntry e{key_info(key, accepted, std::move(description), ref(defaults)), nullptr,
             [ref](Scene s) { return ref(s); }};
  e.set = [ref](Scene& s, const std::string& value) { ref(s) = value; };
  return e;
}

template <class Enum, std::size_t N, class Ref>
KeyEntry choice(std::string key, const std::array<Enum, N>& all, std::string description, Ref ref_fn) {
  const std::function<Enum&(Scene&)> ref = ref_fn;
  std::string accepted = "one of";
  for (const Enum v : all) accepted += std::string(" ") + to_string(v);
  Scene defaults;
  KeyEntry e{key_info(key, accepted, std::move(description), to_string(ref(defaults))), nullptr,
             [ref](Scene s) { return std::string(to_string(ref(s))); }};
  e.set = [key, all, accepted, ref](Scene& s, const std::string& text) {
    for (const Enum v : all) {
      if (text == to_string(v)) {
        ref(s) = v;
        return;
      }
    }
    throw SceneError("scene key '" + key + "': value '" + text + "' is not accepted; accepted: " + accepted);
  };
  return e;
}

// Which keys a running machine may change, and why the others may not
// (Simulation::change_parameters states what a change does to the state).
void mark_live(SceneKeyInfo& info) {
  // A cracked shaft, blade loss (magnitude and phase), a loosened support,
  // thermal growth or seal wear, a casing that moves, the contact's state,
  // a retuned drive.
  static const std::set<std::string> kLive = {
      "rotor_stiffness_N_per_m",
      "rotor_damping_N_s_per_m",
      "eccentricity_m",
      "unbalance_phase_rad",
      "stator_stiffness_N_per_m",
      "stator_damping_N_s_per_m",
      "clearance_m",
      "stator_offset_x_m",
      "stator_offset_y_m",
      "friction_coefficient",
      "restitution",
      "impact_settle_velocity_m_per_s",
      "contact_stiffness_N_per_m",
      "contact_damping_N_s_per_m",
      "drive_torque_limit_N_m",
      "drive_proportional_gain_N_m_s_per_rad",
      "drive_integral_gain_N_m_per_rad",
  };
  if (kLive.count(info.key) != 0) {
    info.live = true;
    return;
  }
  const std::string& k = info.key;
  if (k == "stator_model" || k == "drive_model") {
    info.live_refusal = "it sets the model's structure (its state's size)";
  } else if (k == "rotor_mass_kg" || k == "stator_mass_kg" || k == "rotor_polar_inertia_kg_m2" ||
             k == "rotor_radius_m") {
    info.live_refusal =
        "a mass, an inertia or the rotor's radius has no continuous path for the state (a blade "
        "loss is an unbalance change: eccentricity_m, unbalance_phase_rad)";
  } else if (k == "rotor_file" || k == "rotor_planar_modes" || k == "rotor_probe_node" ||
             k == "rotor_truncation_tolerance") {
    info.live_refusal = "it sets the rotor (its state's size)";
  } else if (k == "gravity_m_per_s2") {
    info.live_refusal = "the machine's orientation is fixed";
  } else if (k.rfind("initial_", 0) == 0) {
    info.live_refusal = "an initial condition applies at t = 0 only";
  } else if (k.rfind("probe_", 0) == 0) {
    info.live_refusal = "the probes are mounted for the whole run";
  } else if (k == "acceleration_rad_per_s2" || k == "target_speed_rad_per_s" || k == "max_speed_rad_per_s") {
    info.live_refusal = "the speed is changed by a speed command (topic speed_command)";
  } else {
    info.live_refusal = "it sets the numerics or the run, fixed when the run starts";
  }
}

const std::vector<KeyEntry>& entries() {
  static const std::vector<KeyEntry> table = [] {
    std::vector<KeyEntry> t;
    // Model (paper Table 1 defaults).
    t.push_back(real("rotor_mass_kg", 0, true, kInf, "rotor mass m_r [kg]",
                     [](Scene& s) -> double& { return s.model.rotor_mass_kg; }));
    t.push_back(real("rotor_stiffness_N_per_m", 0, true, kInf, "rotor shaft stiffness k_r [N/m]",
                     [](Scene& s) -> double& { return s.model.rotor_stiffness_N_per_m; }));
    t.push_back(real("rotor_damping_N_s_per_m", 0, false, kInf, "rotor damping b_r [N s/m]",
                     [](Scene& s) -> double& { return s.model.rotor_damping_N_s_per_m; }));
    t.push_back(real("rotor_radius_m", 0, false, kInf, "rotor radius at the contact R_r [m]",
                     [](Scene& s) -> double& { return s.model.rotor_radius_m; }));
    t.push_back(real("eccentricity_m", 0, false, kInf, "mass-centre eccentricity e [m]",
                     [](Scene& s) -> double& { return s.model.eccentricity_m; }));
    t.push_back(real("unbalance_phase_rad", -kInf, false, kInf,
                     "the unbalance's angle on the shaft from the keyphasor's notch, counter-clockwise [rad]",
                     [](Scene& s) -> double& { return s.model.unbalance_phase_rad; }));
    t.push_back(choice("stator_model", kAllStatorModels,
                       "elastic: stator on springs (4 DOF); rigid: fixed stator, rotor's 2 DOF only",
                       [](Scene& s) -> StatorModel& { return s.model.stator_model; }));
    t.push_back(real("stator_mass_kg", 0, true, kInf, "stator mass m_s [kg] (elastic stator)",
                     [](Scene& s) -> double& { return s.model.stator_mass_kg; }));
    t.push_back(real("stator_stiffness_N_per_m", 0, false, kInf, "stator support stiffness k_s [N/m]",
                     [](Scene& s) -> double& { return s.model.stator_stiffness_N_per_m; }));
    t.push_back(real("stator_damping_N_s_per_m", 0, false, kInf, "stator support damping b_s [N s/m]",
                     [](Scene& s) -> double& { return s.model.stator_damping_N_s_per_m; }));
    t.push_back(real("clearance_m", 0, true, kInf, "radial clearance C [m]",
                     [](Scene& s) -> double& { return s.model.clearance_m; }));
    t.push_back(real("friction_coefficient", 0, false, 2.0, "Coulomb friction coefficient f [-]; 0 skips friction",
                     [](Scene& s) -> double& { return s.model.friction_coefficient; }));
    t.push_back(real("restitution", 0, false, 1.0, "normal coefficient of restitution [-]; 0 plastic, 1 elastic",
                     [](Scene& s) -> double& { return s.model.restitution; }));
    t.push_back(real("impact_settle_velocity_m_per_s", 0, false, kInf,
                     "rebound speed below which an impact settles into contact [m/s]",
                     [](Scene& s) -> double& { return s.model.impact_settle_velocity_m_per_s; }));
    t.push_back(real("contact_stiffness_N_per_m", 0, true, kInf, "penalty contact stiffness k_c [N/m] (method I)",
                     [](Scene& s) -> double& { return s.model.contact_stiffness_N_per_m; }));
    t.push_back(real("contact_damping_N_s_per_m", 0, false, kInf,
                     "penalty contact damper c_c [N s/m] (method I), in place of the restitution's; 0: from "
                     "restitution (the summary's contact_point gives the mass that converts one into the other)",
                     [](Scene& s) -> double& { return s.model.contact_damping_N_s_per_m; }));
    t.push_back(real("gravity_m_per_s2", 0, false, 100.0, "gravity along -y [m/s^2]; 0 for a vertical machine",
                     [](Scene& s) -> double& { return s.model.gravity_m_per_s2; }));
    t.push_back(real("stator_offset_x_m", -1.0, false, 1.0,
                     "stator rest position, x (a misaligned casing: partial rub); |offset| < clearance_m [m]",
                     [](Scene& s) -> double& { return s.model.stator_offset_x_m; }));
    t.push_back(real("stator_offset_y_m", -1.0, false, 1.0, "stator rest position, y; |offset| < clearance_m [m]",
                     [](Scene& s) -> double& { return s.model.stator_offset_y_m; }));
    // A flexible rotor (docs/rotors.md).
    t.push_back(text("rotor_file", "a rotor file's path (docs/rotors.md), or empty",
                     "a flexible rotor in place of the Jeffcott: shaft, disks, bearings, unbalances, rub station "
                     "(rotor_mass_kg, rotor_stiffness_N_per_m, rotor_damping_N_s_per_m, eccentricity_m and "
                     "rotor_radius_m are then the file's); every method, on its integrators of --list-solvers",
                     [](Scene& s) -> std::string& { return s.rotor.file; }));
    t.push_back(integer_or_auto(
        "rotor_planar_modes", 1, kMaxPlanarModes,
        "a flexible rotor's planar modes kept: the rub station and rotor_planar_modes - 1 shaft shapes per plane "
        "(the planes' static corrections and modes, lowest first), up to the rotor's planar DOFs (2 per node and 1 "
        "per support node: the full FE model of a rotor of up to 256 nodes); auto: the fewest whose unbalance response "
        "at the station "
        "and the probes is within rotor_truncation_tolerance of the full model's over the run's speeds",
        [](Scene& s) -> long& { return s.rotor.planar_modes; }));
    t.push_back(real("rotor_truncation_tolerance", 0, true, 1.0,
                     "rotor_planar_modes auto's bound on the unbalance response's error, relative to the rotor's "
                     "largest displacement [-]",
                     [](Scene& s) -> double& { return s.rotor.truncation_tolerance; }));
    t.push_back(integer("rotor_probe_node", -1, 100000,
                        "the node of a flexible rotor the X/Y probes read (probe_*); -1: the rotor file's first "
                        "probe node, else the rub station",
                        [](Scene& s) -> long& { return s.rotor.probe_node; }));
    // Drive.
    t.push_back(choice("drive_model", kAllDriveModels,
                       "prescribed: the speed profile is the spin; motor: a PI speed-controlled motor "
                       "drives the spin against the rub's friction torque",
                       [](Scene& s) -> DriveModel& { return s.model.drive_model; }));
    t.push_back(real("rotor_polar_inertia_kg_m2", 0, true, kInf,
                     "polar moment of inertia of the rotating train: the Jeffcott's J_G about its mass centre; a "
                     "rotor_file's J about the shaft axis [kg m^2]",
                     [](Scene& s) -> double& { return s.model.rotor_polar_inertia_kg_m2; }));
    t.push_back(real("drive_torque_limit_N_m", 0, true, kInf, "motor torque limit, motoring and braking [N m]",
                     [](Scene& s) -> double& { return s.model.drive_torque_limit_N_m; }));
    t.push_back(real("drive_proportional_gain_N_m_s_per_rad", 0, true, kInf,
                     "speed controller's proportional gain K_p [N m s/rad]",
                     [](Scene& s) -> double& { return s.model.drive_proportional_gain_N_m_s_per_rad; }));
    t.push_back(real("drive_integral_gain_N_m_per_rad", 0, false, kInf,
                     "speed controller's integral gain K_i [N m/rad]; 0: proportional only",
                     [](Scene& s) -> double& { return s.model.drive_integral_gain_N_m_per_rad; }));
    t.push_back(real("initial_angle_rad", -kInf, false, kInf, "spin angle at t = 0 [rad]",
                     [](Scene& s) -> double& { return s.speed.initial_angle_rad; }));
    t.push_back(real("initial_speed_rad_per_s", 0, false, kInf, "spin speed at t = 0 [rad/s]",
                     [](Scene& s) -> double& { return s.speed.initial_speed_rad_per_s; }));
    t.push_back(real("acceleration_rad_per_s2", 0, false, kInf,
                     "angular acceleration toward the target [rad/s^2]; 0 for a constant speed (the target "
                     "then equal to the initial speed)",
                     [](Scene& s) -> double& { return s.speed.acceleration_rad_per_s2; }));
    t.push_back(real("target_speed_rad_per_s", 0, false, kInf, "target spin speed [rad/s]; held once reached",
                     [](Scene& s) -> double& { return s.speed.target_speed_rad_per_s; }));
    t.push_back(real("max_speed_rad_per_s", 0, true, kInf, "largest speed a scene or command may ask [rad/s]",
                     [](Scene& s) -> double& { return s.speed.max_speed_rad_per_s; }));
    // Numerics.
    t.push_back(choice("method", kAllMethods, "contact method: penalty (I), switching (II), iteration (III)",
                       [](Scene& s) -> Method& { return s.solver.method; }));
    t.push_back(choice("integrator", kAllIntegrators,
                       "time integrator; auto: the method's usual fastest at the rtol (" + auto_integrator_text() +
                           "); each method's integrators: rotor_rub_run --list-solvers",
                       [](Scene& s) -> Integrator& { return s.solver.integrator; }));
    t.push_back(real("rtol", 1e-14, false, 1.0, "relative error tolerance per step [-]",
                     [](Scene& s) -> double& { return s.solver.rtol; }));
    t.push_back(real("atol", 1e-16, false, 1.0, "absolute error tolerance per step [m, m/s]",
                     [](Scene& s) -> double& { return s.solver.atol; }));
    t.push_back(real("initial_step_s", 0, true, 1.0, "first trial step [s]",
                     [](Scene& s) -> double& { return s.solver.initial_step_s; }));
    t.push_back(real("fixed_step_s", 0, true, 1e-2, "the fixed step h of integrator rk4 [s]",
                     [](Scene& s) -> double& { return s.solver.fixed_step_s; }));
    t.push_back(real("min_step_s", 0, true, 1.0, "smallest step before a run is declared stalled [s]",
                     [](Scene& s) -> double& { return s.solver.min_step_s; }));
    t.push_back(integer("max_steps", 1, 2'000'000'000L, "budget of accepted plus rejected steps",
                        [](Scene& s) -> long& { return s.solver.max_steps; }));
    t.push_back(real("max_wall_time_s", 0, true, 1e7, "wall-time budget of the integration; beyond it: timed_out [s]",
                     [](Scene& s) -> double& { return s.solver.max_wall_time_s; }));
    t.push_back(real("iteration_force_rtol", 1e-15, false, 1e-2,
                     "method III: relative tolerance on the normal force root [-]",
                     [](Scene& s) -> double& { return s.solver.iteration_force_rtol; }));
    t.push_back(integer("iteration_max_iterations", 1, 1000,
                        "method III: root-finder evaluations per normal force solve before not_converged",
                        [](Scene& s) -> long& { return s.solver.iteration_max_iterations; }));
    t.push_back(real("max_events_per_ms", 0, true, kInf,
                     "contact events per simulated ms above which a run is chattering [1/ms]",
                     [](Scene& s) -> double& { return s.solver.max_events_per_ms; }));
    t.push_back(
        real("end_time_s", 0, true, 1e6, "simulated end time [s]", [](Scene& s) -> double& { return s.end_time_s; }));
    t.push_back(real("output_rate_hz", 0, true, 1e7, "sample rate of the output in simulated time [Hz]",
                     [](Scene& s) -> double& { return s.output_rate_hz; }));
    // Proximity probes (parameters.hpp: on the casing, API 670 mounting).
    t.push_back(real("probe_rate_hz", 0, false, 1e7,
                     "sample rate of the X/Y proximity probes in simulated time, 0 for none [Hz]",
                     [](Scene& s) -> double& { return s.probes.rate_hz; }));
    t.push_back(real("probe_x_angle_rad", -kInf, false, kInf,
                     "X probe's axis, counter-clockwise from +x (pi/4: 45 deg right of top) [rad]",
                     [](Scene& s) -> double& { return s.probes.x_angle_rad; }));
    t.push_back(real("probe_y_angle_rad", -kInf, false, kInf,
                     "Y probe's axis, counter-clockwise from +x (3 pi/4: 45 deg left of top) [rad]",
                     [](Scene& s) -> double& { return s.probes.y_angle_rad; }));
    t.push_back(real("probe_sensitivity_V_per_m", 0, true, kInf, "probe sensitivity (7874: 200 mV/mil) [V/m]",
                     [](Scene& s) -> double& { return s.probes.sensitivity_V_per_m; }));
    t.push_back(real("probe_noise_V", 0, false, kInf, "probe noise, standard deviation, seeded [V]",
                     [](Scene& s) -> double& { return s.probes.noise_V; }));
    t.push_back(integer("probe_noise_seed", 0, 2147483647L, "seed of the probe noise (the same seed, the same noise)",
                        [](Scene& s) -> long& { return s.probes.noise_seed; }));
    t.push_back(real("probe_runout_m", 0, false, kInf,
                     "mechanical/electrical runout seen by the probes: a once-per-revolution pattern [m]",
                     [](Scene& s) -> double& { return s.probes.runout_m; }));
    t.push_back(real("probe_runout_phase_rad", -kInf, false, kInf,
                     "the runout's direction on the shaft, from the keyphasor's notch [rad]",
                     [](Scene& s) -> double& { return s.probes.runout_phase_rad; }));
    for (auto& e : t) mark_live(e.info);
    return t;
  }();
  return table;
}

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

}  // namespace

std::string exact_text(double v) {
  char buf[40];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

const std::vector<SceneKeyInfo>& scene_keys() {
  static const std::vector<SceneKeyInfo> infos = [] {
    std::vector<SceneKeyInfo> v;
    for (const auto& e : entries()) v.push_back(e.info);
    return v;
  }();
  return infos;
}

std::string nearest_key(const std::string& key, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_d = std::numeric_limits<std::size_t>::max();
  for (const auto& c : candidates) {
    const std::size_t d = edit_distance(key, c);
    if (d < best_d) {
      best_d = d;
      best = c;
    }
  }
  return best_d <= std::max<std::size_t>(3, key.size() / 3) ? best : std::string();
}

std::string nearest_scene_key(const std::string& key) {
  std::vector<std::string> names;
  for (const auto& e : entries()) names.push_back(e.info.key);
  return nearest_key(key, names);
}

std::map<std::string, std::string> scene_values(const Scene& scene) {
  std::map<std::string, std::string> values;
  for (const auto& e : entries()) values[e.info.key] = e.get(scene);
  return values;
}

void set_scene_value(Scene& scene, const std::string& key, const std::string& value) {
  for (const auto& e : entries()) {
    if (e.info.key == key) {
      e.set(scene, value);
      return;
    }
  }
  const std::string near = nearest_scene_key(key);
  throw SceneError("unknown scene key '" + key + "'" + (near.empty() ? "" : "; did you mean '" + near + "'?") +
                       " (rotor_rub_run --list-keys prints every key)",
                   key, SceneError::Kind::kUnknownKey);
}

std::string live_key_inert_reason(const std::string& key, const Scene& scene) {
  const bool rigid = scene.model.stator_model == StatorModel::kRigid;
  if (rigid && (key == "stator_stiffness_N_per_m" || key == "stator_damping_N_s_per_m")) {
    return "it has no effect on a rigid stator (stator_model rigid)";
  }
  if ((key == "contact_stiffness_N_per_m" || key == "contact_damping_N_s_per_m") &&
      scene.solver.method != Method::kPenalty) {
    return "it applies to the penalty method only";
  }
  if (scene.model.drive_model != DriveModel::kMotor && key.rfind("drive_", 0) == 0) {
    return "it applies to drive_model motor only";
  }
  if (rotor_kind(scene) == RotorKind::kFlexible &&
      (key == "rotor_stiffness_N_per_m" || key == "rotor_damping_N_s_per_m" || key == "eccentricity_m")) {
    return "the rotor is rotor_file's (its shaft, bearings and unbalances)";
  }
  return "";
}

Scene scene_from_values(const std::map<std::string, std::string>& values,
                        std::shared_ptr<const LoadedFlexibleRotor> loaded) {
  Scene s;
  for (const auto& [k, v] : values) set_scene_value(s, k, v);
  s.rotor.loaded = std::move(loaded);
  // A flexible rotor's file is read here once (unless given the one it
  // names) and validated from what was read; a file that cannot be read is
  // read again by validate_scene, which names the key.
  try {
    load_rotor(s);
  } catch (const std::invalid_argument&) {
  }
  validate_scene(s);
  return s;
}

}  // namespace rotor_rub::core
