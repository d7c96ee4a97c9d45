#include "rotor_rub_sim/core/faults.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"

namespace rotor_rub::core {
namespace {

[[noreturn]] void refuse(const char* field, double v, const std::string& accepted) {
  std::ostringstream os;
  os << "fault " << field << " ";
  if (std::isnan(v)) {
    os << "NaN";
  } else {
    os << v;
  }
  os << " is " << (std::isfinite(v) ? "out of range" : "not a finite number") << "; accepted: " << accepted;
  throw std::invalid_argument(os.str());
}

// A step at the fault's instant changing these keys.
FaultStep step_of(std::map<std::string, std::string> changes) {
  FaultStep step;
  step.changes = std::move(changes);
  return step;
}

// The unbalance a blade loss adds at its node of a flexible rotor, in the
// file's angles: the lost one turned by pi, less the scene's
// unbalance_phase_rad (which turns every unbalance of the file).
RotorUnbalance flexible_blade_loss(const Fault& f, const Scene& now) {
  const auto rotor = flexible_rotor_of(now);
  const std::vector<int>& disks = rotor->disk_nodes();
  const bool on_disk = disks.empty() ? f.node >= 0 && f.node < rotor->nodes()
                                     : std::find(disks.begin(), disks.end(), f.node) != disks.end();
  if (!on_disk) {
    std::ostringstream os;
    os << "fault node " << f.node << " is out of range; accepted for '" << now.rotor.file << "': ";
    if (disks.empty()) {
      os << "0 to " << rotor->nodes() - 1;
    } else {
      os << "a node with a disk (";
      for (std::size_t i = 0; i < disks.size(); ++i) os << (i ? ", " : "") << disks[i];
      os << ")";
    }
    throw std::invalid_argument(os.str());
  }
  return {f.node, f.magnitude, f.phase_rad + M_PI - now.model.unbalance_phase_rad};
}

}  // namespace

const char* to_string(FaultKind k) {
  switch (k) {
    case FaultKind::kBladeLoss:
      return "blade_loss";
    case FaultKind::kThermalClosure:
      return "thermal_closure";
    case FaultKind::kSealWear:
      return "seal_wear";
    case FaultKind::kFrictionChange:
      return "friction_change";
    case FaultKind::kSupportLoosening:
      return "support_loosening";
  }
  throw std::logic_error("to_string: not a FaultKind");
}

void check_fault(const Fault& f) {
  if (!std::isfinite(f.magnitude) || f.magnitude < 0.0) refuse("magnitude", f.magnitude, "[0, inf)");
  if (f.kind == FaultKind::kSupportLoosening && !(f.magnitude < 1.0)) {
    refuse("magnitude", f.magnitude, "[0, 1) for support_loosening (the fraction of stiffness lost)");
  }
  if (!std::isfinite(f.phase_rad)) refuse("phase", f.phase_rad, "a finite angle [rad]");
  const bool ramps = f.kind == FaultKind::kThermalClosure || f.kind == FaultKind::kSealWear;
  if (!std::isfinite(f.duration_s) || f.duration_s < 0.0 || (!ramps && f.duration_s != 0.0)) {
    refuse("duration", f.duration_s, ramps ? "[0, inf) (0: a step)" : "0 (this fault is a step)");
  }
}

void check_fault(const Fault& f, double output_rate_hz) {
  check_fault(f);
  // A ramp's steps are queued at once: at most kMaxRampSteps of them.
  if (f.duration_s * output_rate_hz > static_cast<double>(kMaxRampSteps)) {
    std::ostringstream os;
    os << "[0, " << static_cast<double>(kMaxRampSteps) / output_rate_hz << "] s at output_rate_hz " << output_rate_hz
       << " (one step per output sample, at most " << kMaxRampSteps << " steps)";
    refuse("duration", f.duration_s, os.str());
  }
}

std::vector<FaultStep> fault_steps(const Fault& f, const Scene& scene, double output_rate_hz) {
  check_fault(f, output_rate_hz);
  const ModelParameters& now = scene.model;
  std::vector<FaultStep> steps;
  switch (f.kind) {
    case FaultKind::kBladeLoss: {
      if (rotor_kind(scene) == RotorKind::kFlexible) {
        FaultStep step;
        step.unbalances_added.push_back(flexible_blade_loss(f, scene));
        steps.push_back(step);
        break;
      }
      if (f.node != 0) {
        throw std::invalid_argument("fault node " + std::to_string(f.node) +
                                    " is out of range; accepted: 0 (the Jeffcott rotor's one disk)");
      }
      const std::complex<double> u = now.rotor_mass_kg * now.eccentricity_m * std::polar(1.0, now.unbalance_phase_rad) -
                                     std::polar(f.magnitude, f.phase_rad);
      steps.push_back(step_of({{"eccentricity_m", exact_text(std::abs(u) / now.rotor_mass_kg)},
                               {"unbalance_phase_rad", exact_text(std::arg(u))}}));
      break;
    }
    case FaultKind::kThermalClosure:
    case FaultKind::kSealWear: {
      const double sign = f.kind == FaultKind::kSealWear ? 1.0 : -1.0;
      const long n = f.duration_s > 0.0 ? std::max(1L, std::lround(std::ceil(f.duration_s * output_rate_hz))) : 1;
      for (long k = 1; k <= n; ++k) {
        const double share = static_cast<double>(k) / static_cast<double>(n);
        FaultStep step;
        step.offset_s = f.duration_s * share;
        step.changes["clearance_m"] = exact_text(now.clearance_m + sign * f.magnitude * share);
        step.stop_at_rotor = f.kind == FaultKind::kThermalClosure;
        steps.push_back(step);
      }
      break;
    }
    case FaultKind::kFrictionChange:
      steps.push_back(step_of({{"friction_coefficient", exact_text(f.magnitude)}}));
      break;
    case FaultKind::kSupportLoosening:
      steps.push_back(
          step_of({{"stator_stiffness_N_per_m", exact_text(now.stator_stiffness_N_per_m * (1.0 - f.magnitude))}}));
      break;
  }
  return steps;
}

}  // namespace rotor_rub::core
