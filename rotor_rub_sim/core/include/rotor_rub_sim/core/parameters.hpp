/// @file
/// Plain configuration structs of the simulation core (no ROS, no YAML here).
/// Units are SI and stated in the member names. Defaults are the paper's Table 1
/// (Hynek 2002) where the paper gives a value.
#pragma once

#include <array>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace rotor_rub::core {

// ---- Enum-like choices ------------------------------------------------------
/// Names through to_string (a switch the compiler checks for every value);
/// *_from_string reads them back and names the accepted ones. Which
/// integrators each method runs on is solver_registry.hpp's one table.

/// The paper's contact methods: I penalty spring, II switching between the
/// free and the contact equations at located events, III the contact force
/// iterated at every evaluation (docs/numerics.md).
enum class Method { kPenalty, kSwitching, kIteration };
/// kAuto: the registry's choice for the method and the rtol (the fastest
/// there at dopri5's accuracy or better, solver_registry.cpp), resolved when
/// a run starts.
enum class Integrator { kAuto, kDopri5, kRosenbrock4, kRk4, kRkf78, kDop853, kDop853Rosenbrock4 };
/// The stator: elastic (mass, springs, dampers: the paper's) or rigid (fixed).
enum class StatorModel { kElastic, kRigid };
/// The spin: prescribed by the speed profile (the paper's), or a motor's
/// state under a speed controller (ModelParameters::drive_model).
enum class DriveModel { kPrescribed, kMotor };

/// The kind of rotor a scene runs (the solver registry's third dimension,
/// after the method and the integrator): the paper's Jeffcott, or a flexible
/// rotor read from a rotor_file (rotor_model.hpp).
enum class RotorKind { kJeffcott, kFlexible };

/// Every method, in the order --help lists them (the paper's).
inline constexpr std::array<Method, 3> kAllMethods{Method::kPenalty, Method::kSwitching, Method::kIteration};
/// Every integrator, `auto` first, in the order --help lists them.
inline constexpr std::array<Integrator, 7> kAllIntegrators{
    Integrator::kAuto,  Integrator::kDopri5, Integrator::kRosenbrock4,      Integrator::kRk4,
    Integrator::kRkf78, Integrator::kDop853, Integrator::kDop853Rosenbrock4};
/// Every kind of rotor.
inline constexpr std::array<RotorKind, 2> kAllRotorKinds{RotorKind::kJeffcott, RotorKind::kFlexible};
/// Every stator model, in the order --help lists them.
inline constexpr std::array<StatorModel, 2> kAllStatorModels{StatorModel::kElastic, StatorModel::kRigid};
/// Every drive model, in the order --help lists them.
inline constexpr std::array<DriveModel, 2> kAllDriveModels{DriveModel::kPrescribed, DriveModel::kMotor};

/// The method's name, as scene files, --help and the outputs write it.
const char* to_string(Method m);
/// The integrator's name (`auto` for kAuto), as scene files and --help write it.
const char* to_string(Integrator i);
/// The stator model's name: elastic, rigid.
const char* to_string(StatorModel s);
/// The drive model's name: prescribed, motor.
const char* to_string(DriveModel d);
/// The rotor kind's name: jeffcott, flexible.
const char* to_string(RotorKind r);
/// The value of `all` whose to_string is s (any enum with a to_string and a
/// kAll array: these, the event kinds, the node's end_action). Throws
/// std::invalid_argument naming what, s and the accepted names.
template <class Enum, std::size_t N>
Enum value_named(const std::array<Enum, N>& all, const std::string& s, const char* what) {
  std::string accepted;
  for (const Enum v : all) {
    if (s == to_string(v)) return v;
    accepted += std::string(accepted.empty() ? "" : ", ") + to_string(v);
  }
  throw std::invalid_argument(std::string(what) + " '" + s + "' is not accepted; accepted: " + accepted);
}

/// The method named s; throws std::invalid_argument naming the accepted names.
Method method_from_string(const std::string& s);
/// The integrator named s (`auto` too); throws as method_from_string.
Integrator integrator_from_string(const std::string& s);
/// The stator model named s; throws as method_from_string.
StatorModel stator_model_from_string(const std::string& s);
/// The drive model named s; throws as method_from_string.
DriveModel drive_model_from_string(const std::string& s);

// ---- Physical model ---------------------------------------------------------

/// The Jeffcott rotor, the stator, the contact and the drive (model.hpp
/// states the equations).
struct ModelParameters {
  double rotor_mass_kg = 0.418;             ///< m_r
  double rotor_stiffness_N_per_m = 2493.0;  ///< k_r: the shaft's
  double rotor_damping_N_s_per_m = 1.3;     ///< b_r: the shaft's
  double rotor_radius_m = 0.010;            ///< R_r: contact point radius (sliding velocity)
  double eccentricity_m = 0.4e-3;           ///< e: mass centre to geometric centre
  /// beta: the unbalance's angle on the shaft, counter-clockwise from the
  /// keyphasor's notch: the mass centre lies along phi + beta (0: the
  /// notch's direction, the paper's unbalance).
  double unbalance_phase_rad = 0.0;
  StatorModel stator_model = StatorModel::kElastic;  ///< elastic (the paper's) or rigid
  double stator_mass_kg = 0.86;                      ///< m_s (elastic stator)
  double stator_stiffness_N_per_m = 38166.0;         ///< k_s: its supports' (elastic stator)
  double stator_damping_N_s_per_m = 3.61;            ///< b_s: its supports' (elastic stator)
  double clearance_m = 2.0e-3;                       ///< C: radial clearance
  double friction_coefficient = 0.1;                 ///< f: Coulomb (stick and slip, contact_law.hpp)
  double restitution = 0.0;                          ///< normal coefficient of restitution, 0 = plastic
  /// Impacts whose rebound velocity falls below this settle into sustained
  /// contact (ends a Zeno sequence of ever smaller bounces).
  double impact_settle_velocity_m_per_s = 1.0e-6;
  double contact_stiffness_N_per_m = 1.0e9;  ///< k_c, penalty method only
  /// c_c [N s/m], penalty method only: the contact's damper as most papers
  /// and ROSS give it; 0: from the restitution (contact_law.hpp). One of the
  /// two: validate_scene refuses both.
  double contact_damping_N_s_per_m = 0.0;
  double gravity_m_per_s2 = 0.0;  ///< along -y; 0: vertical machine, as in the paper
  /// The stator's rest position (a misaligned or thermally bowed casing): the
  /// centre its springs pull it to, or where a rigid stator sits. A static
  /// offset below the clearance gives partial rub on one side.
  double stator_offset_x_m = 0.0;  ///< along x
  double stator_offset_y_m = 0.0;  ///< along y
  /// The drive (model.hpp): prescribed, the speed profile is the spin; motor,
  /// the spin is a state driven by a PI speed controller (with acceleration
  /// feed-forward, a torque limit and back-calculation anti-windup) that
  /// follows the speed profile, against the rub's friction torque.
  DriveModel drive_model = DriveModel::kPrescribed;
  /// J_G: the rotating train's polar moment of inertia about the spin axis
  /// through its mass centre (disc, shaft, coupling, motor rotor) [kg m^2].
  /// The prescribed drive uses it only to report the torque it applies.
  double rotor_polar_inertia_kg_m2 = 1.0e-3;
  double drive_torque_limit_N_m = 0.5;                 ///< |T_m| <= limit (motoring and braking)
  double drive_proportional_gain_N_m_s_per_rad = 0.1;  ///< K_p: per rad/s of speed error
  double drive_integral_gain_N_m_per_rad = 2.5;        ///< K_i: per rad of integrated speed error
};

// ---- Drive: piecewise constant angular acceleration ------------------------

/// The speed profile the drive follows: from the initial speed toward the
/// target at constant acceleration, then held (speed_profile.hpp); speed
/// commands replace the target later.
struct SpeedProfileParameters {
  double initial_angle_rad = 0.0;         ///< phi at t = 0
  double initial_speed_rad_per_s = 0.0;   ///< omega at t = 0
  double acceleration_rad_per_s2 = 70.0;  ///< magnitude used toward the target
  double target_speed_rad_per_s = 280.0;  ///< 70 rad/s^2 for 4 s, as in the paper
  double max_speed_rad_per_s = 2000.0;    ///< limit for speed commands
};

// ---- Numerical settings ----------------------------------------------------

/// How a scene is integrated: the method, the integrator and their
/// tolerances and budgets.
struct SolverSettings {
  Method method = Method::kSwitching;         ///< where contact is handled (numerics.md)
  Integrator integrator = Integrator::kAuto;  ///< the registry's pair with method; auto: its pick
  double rtol = 1.0e-6;                       ///< relative tolerance per step
  double atol = 1.0e-9;                       ///< applies to every state component (m and m/s)
  double initial_step_s = 1.0e-5;             ///< the first trial step
  double fixed_step_s = 1.0e-6;               ///< integrator rk4 only: the fixed step h
  double min_step_s = 1.0e-14;                ///< below it a run is declared stalled
  long max_steps = 20'000'000;                ///< accepted + rejected step budget
  /// Wall-time budget of the integration (cost, not simulated time): a run
  /// that spends it fails as timed_out instead of hanging a sweep or a node.
  double max_wall_time_s = 600.0;
  /// Method III: relative tolerance on the normal force root.
  double iteration_force_rtol = 1.0e-12;
  long iteration_max_iterations = 100;  ///< root-finder evaluations per solve
  /// Switching/iteration: more contact events than this per simulated
  /// millisecond is chattering, reported as stalled.
  double max_events_per_ms = 200.0;
  /// Benchmark only (not a scene key): measure the time spent in derivative
  /// evaluation, force iteration, event location, restarts and output
  /// (RunStats::rhs_time_s, iteration_time_s, event_time_s, restart_time_s,
  /// output_time_s).
  bool profile_cost = false;
};

// ---- Proximity probes (what a machinery-protection system reads) -----------
/// An X/Y pair of eddy-current probes on the casing (the inertial frame, not
/// the elastically supported stator), each measuring the rotor centre's
/// displacement along its axis, at angle theta counter-clockwise from +x.
/// The default mounting is API 670's: 45 deg right (X) and 45 deg left (Y) of
/// top dead centre (+y). The signal is the dynamic (AC) part in volts:
///   v = S (r_r . u_theta + runout(phi) . u_theta) + noise,
/// runout(phi) = runout (cos(phi + runout_phase), sin(phi + runout_phase)) a
/// once-per-revolution pattern fixed to the shaft (mechanical/electrical
/// runout), noise Gaussian with a fixed seed.
struct ProbeParameters {
  double rate_hz = 0.0;                                ///< 0: no probe signals
  double x_angle_rad = 0.25 * 3.14159265358979323846;  ///< the X probe's direction from +x
  double y_angle_rad = 0.75 * 3.14159265358979323846;  ///< the Y probe's direction from +x
  double sensitivity_V_per_m = 7874.0;                 ///< 200 mV/mil (API 670)
  double noise_V = 0.0;                                ///< standard deviation
  long noise_seed = 1;                                 ///< the noise's seed: the same signals every run
  double runout_m = 0.0;                               ///< the runout pattern's amplitude
  double runout_phase_rad = 0.0;                       ///< the runout pattern's phase on the shaft
};

// ---- A flexible rotor (docs/rotors.md) ---------------------------------------
struct LoadedFlexibleRotor;  // flexible_rotor_model.hpp

/// In place of the Jeffcott rotor of the model's rotor keys: a rotor file's
/// shaft, disks and bearings (or its matrices), reduced at its rub station
/// to planar_modes per plane (rotor_reduction.hpp). The contact keys apply
/// at the station.
struct RotorSettings {
  std::string file;  ///< the rotor file; empty: the Jeffcott rotor
  /// The station and planar_modes - 1 shaft shapes, per plane; 0: auto, the
  /// fewest whose unbalance response is within truncation_tolerance of the
  /// full model's over the scene's speeds (load_flexible_rotor).
  long planar_modes = 8;
  double truncation_tolerance = 1e-3;  ///< auto's bound, relative to the largest displacement
  /// The node the X/Y proximity probes read (ProbeParameters); -1: the
  /// rotor file's first probe node, else the rub station.
  long probe_node = -1;
  /// The file read and reduced once (scene_from_values, Simulation), with
  /// what it was read for: validation, the methods and live changes share it
  /// (flexible_rotor_of). Not a key: a scene's copies share it.
  std::shared_ptr<const LoadedFlexibleRotor> loaded;
};

/// Everything a run needs: what scene files, rosparam and --set fill
/// (scene_keys.hpp names every key). Simulation validates it
/// (validate_scene).
struct Scene {
  ModelParameters model;           ///< the rotor, stator, contact and drive
  RotorSettings rotor;             ///< a flexible rotor's file and reduction, or none
  SpeedProfileParameters speed;    ///< the drive's speed profile
  SolverSettings solver;           ///< the method, the integrator, tolerances and budgets
  ProbeParameters probes;          ///< the proximity probes' signals
  double end_time_s = 4.0;         ///< the run's simulated end
  double output_rate_hz = 1000.0;  ///< the samples' rate in simulated time
};

/// The scene's kind of rotor: flexible when it names a rotor_file.
inline RotorKind rotor_kind(const Scene& scene) {
  return scene.rotor.file.empty() ? RotorKind::kJeffcott : RotorKind::kFlexible;
}

}  // namespace rotor_rub::core
