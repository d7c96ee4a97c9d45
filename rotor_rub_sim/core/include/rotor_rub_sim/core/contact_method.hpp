/// @file
/// The interface of a contact method: it owns its integrator and internal
/// state, advances one accepted step at a time, and answers the physical state
/// anywhere inside its last step (dense output), so output sampling never
/// shortens a step.
#pragma once

#include <memory>
#include <stdexcept>
#include <vector>

#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/run_types.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"

namespace rotor_rub::core {

class FlexibleRotorModel;

/// One of the paper's methods on one integrator (solver_registry.hpp): the
/// Simulation drives it; a library user may drive one alone (no validation,
/// no invariants' checks: make_contact_method).
class ContactMethod {
 public:
  virtual ~ContactMethod() = default;

  /// Starts integration at t_s from a physical state under a drive segment.
  /// Until the first step, [step_begin(), step_end()] is the instant t_s,
  /// where sample() answers that state.
  virtual void start(double t_s, const Kinematics& k, const SpeedSegment& segment) = 0;
  /// A flexible rotor's start with its modal block [xi; xi'] given (start()
  /// starts it at rest): a run from any state, e.g. a little off a steady
  /// motion (test_full_rub_stability). Throws std::invalid_argument for a
  /// block of the wrong size; the Jeffcott's methods have none:
  /// std::logic_error (the rotor model's check_block, rotor_model.hpp).
  virtual void start_with_modes(double t_s, const Kinematics& k, const SpeedSegment& segment,
                                const ModalState& modal) = 0;

  /// Restarts integration at t_s in [step_begin(), step_end()] from the
  /// method's own state there, under a new drive segment (a drive
  /// discontinuity): the interval becomes the instant t_s. The contact
  /// regime carries over.
  virtual void change_segment(double t_s, const SpeedSegment& segment) = 0;

  /// Restarts at t_s in [step_begin(), step_end()] under new model
  /// parameters of the same structure (a live change: Simulation::
  /// change_parameters, which has checked them). Positions, velocities and
  /// the spin carry over (a rigid stator's offset moves the methods' frame,
  /// not the rotor). A free flight stays free; a contact is decided again as
  /// at a touchdown without closing speed: it lifts off (an event at t_s,
  /// appended to events) when the bore has moved away from the rotor or the
  /// normal force would not be positive, else it goes on, sticking while
  /// the stick force lies inside the new cone, sliding otherwise.
  virtual void change_model(double t_s, const ModelParameters& model, std::vector<ContactEvent>& events) = 0;

  /// A flexible rotor's new model of the same basis (its unbalances changed:
  /// FlexibleRotorModel::with_unbalances) from t_s, the time of the
  /// change_model that follows (Simulation::change_parameters): the step
  /// up to t_s is ended under the old model first (an implicit integrator
  /// takes it again to end there). The Jeffcott's methods have no such
  /// rotor: std::logic_error (the rotor model's replace).
  virtual void change_rotor(double t_s, std::shared_ptr<const FlexibleRotorModel> rotor) = 0;

  /// One accepted step, valid on [step_begin(), step_end()]. An event ends a
  /// step early; so does t_limit_s (the next drive discontinuity or the end
  /// time), where the caller must call change_segment() or stop. Events found
  /// are appended (at times <= step_end()). Throws MethodFailure.
  virtual void step(double t_limit_s, std::vector<ContactEvent>& events) = 0;

  /// The last accepted step's interval [s]: sample() answers inside it.
  virtual double step_begin() const = 0;
  /// The end of the last accepted step [s] (see step_begin()).
  virtual double step_end() const = 0;

  /// The physical state at t_s in [step_begin(), step_end()].
  virtual Sample sample(double t_s) const = 0;

  /// A flexible rotor's model, or nullptr (the Jeffcott).
  virtual const FlexibleRotorModel* flexible_rotor() const { return nullptr; }
  /// A flexible rotor's modal block [xi; xi'] at t_s in [step_begin(),
  /// step_end()]; empty for the Jeffcott.
  virtual ModalState modal_state(double /*t_s*/) const { return ModalState(); }

  /// The cost so far; mutable_stats() lets the Simulation add its own
  /// (the output's time, the wall time).
  virtual const RunStats& stats() const = 0;
  /// The same, writable (see stats()).
  virtual RunStats& mutable_stats() = 0;
};

struct Scene;
/// The method of the scene's method and integrator (`auto` resolved), from
/// the registry; the scene is not validated here (Simulation does that).
std::unique_ptr<ContactMethod> make_contact_method(const Scene& scene);

}  // namespace rotor_rub::core
