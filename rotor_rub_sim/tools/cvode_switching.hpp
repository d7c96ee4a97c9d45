// The switching method (method II, core/switching_method_impl.hpp) on SUNDIALS
// CVODE, for the benchmark only (issue 13): the same model, contact law and
// event logic, integrated by a general-purpose variable-order multistep code
// instead of the core's Dormand-Prince 5(4), so that the two are timed side by
// side in one run. Neither the core nor the node links it (rotor_rub_cvode).
//
// * Free flight: the free state of state_layout.hpp (the rotor model's forces); root
//   function delta - C rising (CVodeRootInit, CVodeSetRootDirection).
// * Contact: ConstrainedDynamics (reduced coordinates), which holds the
//   constraint |r_r - r_s| = C exactly by construction (stronger than
//   Baumgarte stabilisation, which only damps a drift); roots -F_n rising
//   (lift-off) and the friction regime's end (slip: -s v_slide, stick:
//   |F_t,stick| - f F_n, both rising).
// * Events: apply_impact and select_friction_mode (contact_law.hpp), with
//   what follows each event as in the core's SwitchingMethod::on_event().
// * Tolerances: the scene's rtol and scalar atol (CVodeSStolerances).
// * A flexible rotor (a scene's rotor_file): the core's reduced model
//   (FlexibleRotorModel), the station in the contact, the modal block in
//   both regimes' states, and the core's search for a lift-off between the
//   step's ends (the modes ring the normal force).
// Only the prescribed drive; elastic and rigid stators; the Jeffcott and
// flexible rotors.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::tools {

struct CvodeOptions {
  // Adams-Moulton with fixed-point iteration (CVODE's non-stiff choice), or
  // BDF with Newton iteration on a dense difference-quotient Jacobian.
  bool adams = true;
};

struct CvodeRun {
  // SUNContext_Create to the last CVodeFree: all of CVODE's setup, the
  // integration and the events. With sample_rate_hz == 0 no output is made
  // inside it; with samples, their interpolation is inside.
  double wall_time_s = 0;
  long steps = 0;                     // accepted steps, both regimes
  long rhs_evals = 0;                 // f evaluations, the BDF Jacobian's difference quotients included
  long root_evals = 0;                // CVODE's root-function evaluations plus our in-step graze location's
  long error_test_failures = 0;       // steps rejected by the local error test
  long nonlinear_failures = 0;        // steps rejected because the corrector iteration failed
  long events = 0;                    // located events: touchdowns, grazes, lift-offs, friction transitions
  long reinits = 0;                   // CVodeReInit calls: the start, every event, every drive segment break
  std::vector<core::Sample> samples;  // only when sample_rate_hz > 0: at k / rate, 0..end_time_s
  std::vector<core::ContactEvent> events_found;
  std::optional<std::string> failure;  // a CVODE error flag named, or the core's chatter guard
};

// Runs the scene with its solver.rtol, solver.atol, max_steps and
// max_events_per_ms (the other solver settings belong to the core's
// integrators). A motor drive fails at once: "cvode contender: prescribed
// drive only".
CvodeRun run_cvode_switching(const core::Scene& scene, double sample_rate_hz, const CvodeOptions& options = {});

}  // namespace rotor_rub::tools
