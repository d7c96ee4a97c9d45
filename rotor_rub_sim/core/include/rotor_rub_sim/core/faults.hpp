/// @file
/// Faults a monitoring system is tested against, as live parameter changes
/// (Simulation::change_parameters): what each does to the model, stated here.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/fe_rotor.hpp"
#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

enum class FaultKind {
  /// Blade loss: an unbalance m_b r_b [kg m] (magnitude) lost from the angle
  /// phase_rad on the shaft (from the keyphasor's notch). The Jeffcott's
  /// unbalance m e e^(i beta) becomes m e e^(i beta) - m_b r_b e^(i phase):
  /// eccentricity_m and unbalance_phase_rad jump. On a flexible rotor the
  /// lost unbalance is added, opposite, at the disk's node (FaultStep::
  /// unbalances_added). The rotor's mass is kept: m_b is small against it.
  kBladeLoss,
  /// Thermal growth closing the clearance by magnitude [m]; seal wear
  /// opening it by magnitude [m]. A step (duration_s 0) or a ramp over
  /// duration_s, applied as n = ceil(duration_s x output rate) equal steps,
  /// the k-th at k duration_s / n: a staircase as fine as the output, the
  /// clearance constant between its steps. A closure stops where it meets
  /// the rotor (FaultStep::stop_at_rotor): the model's bore does not move
  /// as a body, so a closure cannot press into the rotor; the rub it starts
  /// is the one that begins where the closing bore reaches the orbit.
  kThermalClosure,
  kSealWear,
  /// The friction coefficient becomes magnitude [-].
  kFrictionChange,
  /// A loosened stator support: its stiffness drops by the fraction
  /// magnitude in [0, 1) (elastic stator only).
  kSupportLoosening,
};
inline constexpr FaultKind kAllFaultKinds[] = {FaultKind::kBladeLoss, FaultKind::kThermalClosure, FaultKind::kSealWear,
                                               FaultKind::kFrictionChange, FaultKind::kSupportLoosening};
const char* to_string(FaultKind k);

struct Fault {
  FaultKind kind = FaultKind::kBladeLoss;
  double magnitude = 0.0;   ///< per kind: kg m, m, -, or a fraction
  double phase_rad = 0.0;   ///< blade loss only
  double duration_s = 0.0;  ///< thermal closure and seal wear only: 0 a step, > 0 a ramp
  /// Blade loss only: the node of the disk that loses it (a flexible rotor's
  /// node, one with a disk where the file has disks; the Jeffcott: 0).
  int node = 0;
};

/// One change of a fault: scene keys and values (exact text), at an offset
/// from the fault's instant [s].
struct FaultStep {
  double offset_s = 0.0;
  std::map<std::string, std::string> changes;
  /// A clearance closure: whoever applies it sets clearance_m to no less
  /// than the rotor-stator distance then (Simulation::rotor_stator_distance_m).
  bool stop_at_rotor = false;
  /// A blade loss on a flexible rotor: the unbalance added at its node, in
  /// the file's angles (the scene's unbalance_phase_rad turns it as it turns
  /// the file's own; Simulation::change_parameters).
  std::vector<RotorUnbalance> unbalances_added;
};

/// Throws std::invalid_argument naming the field, the value and the range
/// when a fault is out of range (a negative magnitude, a NaN, a fraction of
/// 1 or more, a ramp on a fault that has none).
void check_fault(const Fault& f);
/// The same, and a ramp of at most kMaxRampSteps steps at this output rate.
inline constexpr long kMaxRampSteps = 100000;
void check_fault(const Fault& f, double output_rate_hz);

/// The changes a fault makes on the scene in force at its instant, in time
/// order (a ramp: one per output sample, the last at duration_s). Checks it
/// first (check_fault, and a blade loss's node on this rotor). The changes
/// themselves are checked when applied (a clearance closed onto the rotor
/// is refused there).
std::vector<FaultStep> fault_steps(const Fault& f, const Scene& now, double output_rate_hz);

}  // namespace rotor_rub::core
