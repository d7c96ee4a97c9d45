// Error measures of a run against a reference run, computed while the run is
// sampled (nothing stored per run), for sweeps of many runs: position errors,
// contact event time errors, and the contact impulse per window.
//
// The impulse per window is what lets the three methods' forces be compared
// at all: a rigid method's impact is an impulse (no force sample carries it)
// and a penalty force oscillates at the contact frequency, far above any
// plotting rate. Over a window W (1 ms by default) every method must transmit
// the same impulse I_W = integral of F_n dt + the impact impulses in W; the
// windowed force I_W / W is the force the methods should agree on.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/simulation.hpp"

namespace rotor_rub::core {

// Contact impulse per window [N s] from samples (trapezoid on F_n; sample
// intervals straddling a window boundary split at the boundary by linear
// interpolation) plus event impulses, on windows [k W, (k+1) W).
class ImpulseWindows {
 public:
  ImpulseWindows() = default;
  explicit ImpulseWindows(double window_s) : window_s_(window_s) {}
  // Restores windows computed earlier (a cached reference).
  ImpulseWindows(double window_s, std::vector<double> impulse_N_s, std::vector<bool> in_contact)
      : window_s_(window_s), impulse_(std::move(impulse_N_s)), contact_(std::move(in_contact)) {}
  void add_sample(double t_s, double normal_force_N, bool in_contact);
  void add_event(const ContactEvent& e);
  double window_s() const { return window_s_; }
  const std::vector<double>& impulse_N_s() const { return impulse_; }
  // Whether any sample or event of the window is in contact.
  const std::vector<bool>& in_contact() const { return contact_; }

 private:
  void add(std::size_t k, double impulse_N_s);
  void mark(std::size_t k);
  double window_s_ = 1e-3;
  std::vector<double> impulse_;
  std::vector<bool> contact_;
  bool have_last_ = false;
  double last_t_s_ = 0.0, last_f_N_ = 0.0;
};

// The reference, compact: what the error measures need, on the sample grid.
struct ReferenceTrace {
  std::vector<double> t_s;
  std::vector<Vec2> rotor_pos_m, stator_pos_m;
  std::vector<ContactEvent> events;
  ImpulseWindows windows;
  bool failed = false;
  std::string failure_message;
};

// The first sample time at which the witness's rotor is farther than
// apart_m from the reference's (a witness that failed first: its last sample
// time; infinity if neither): with a witness that the reference's
// precision cannot tell from it (the same physics computed otherwise, or
// perturbed within a tolerance), the time up to which the motion is
// determined at that precision. Past it a chaotic stick-slip or a run of
// grazing impacts has amplified the difference, so a run that parts from the
// reference there is sensitive, not wrong.
double sensitivity_horizon_s(const ReferenceTrace& reference, const ReferenceTrace& witness, double apart_m);

// Runs the reference scene and keeps its trace.
ReferenceTrace record_reference(const Scene& scene, double window_s = 1e-3);

struct RunErrors {
  std::size_t samples = 0;   // compared (a failed run compares its prefix)
  double max_rotor_m = 0.0;  // max |r_r - r_r,ref| over the samples
  double rms_rotor_m = 0.0;
  double max_stator_m = 0.0;  // max |r_s - r_s,ref|
  double rms_stator_m = 0.0;
  double first_contact_s = 0.0;      // this run's (NaN: none)
  double first_contact_err_s = 0.0;  // minus the reference's (NaN if either has none)
  double last_contact_end_s = 0.0;
  double last_contact_end_err_s = 0.0;
  // Within the horizon the observer was given (all of the run by default):
  double max_rotor_in_horizon_m = 0.0;  // max |r_r - r_r,ref|
  // The contact events (touchdowns, lift-offs, grazes: impacts that leave
  // at once), in order, against the reference's: the largest |t - t_ref|
  // while they agree (same kind, within one impulse window), and the
  // reference's time of the first one that does not (or the run's, for one in
  // excess): a contact missed, added, displaced or ended otherwise; NaN when
  // every one agrees.
  double max_event_err_s = 0.0;
  double event_mismatch_s = 0.0;
  // max over windows where the reference is in contact of
  // |I_W - I_W,ref| / max_W I_W,ref: the windowed force error as a share of
  // the reference's peak windowed force.
  double impulse_window_err_rel = 0.0;
  // Share of those windows whose error is within 5 % of that peak.
  double impulse_windows_within_5pct = 0.0;
  double ref_peak_window_force_N = 0.0;  // max_W I_W,ref / W
  // Physical figures of the run itself (a parameter study reads these).
  double max_orbit_m = 0.0;          // max |r_r|
  double peak_normal_force_N = 0.0;  // max sampled F_n (impacts excluded)
  double contact_time_s = 0.0;       // sampled time in contact
  double stick_time_s = 0.0;         // sampled time in contact and sticking (rolling)
};

// Compares each sample with the reference sample of the same index as it
// arrives. The run must be sampled on the reference's grid (same
// output_rate_hz); a sample off that grid throws std::invalid_argument.
class ErrorObserver : public SimulationObserver {
 public:
  explicit ErrorObserver(const ReferenceTrace& ref, double horizon_s = std::numeric_limits<double>::infinity())
      : ref_(ref), horizon_s_(horizon_s), windows_(ref.windows.window_s()) {}
  void on_sample(const Sample& s) override;
  void on_event(const ContactEvent& e) override;
  // The measures, after the run.
  RunErrors finish() const;

 private:
  void compare_events(const std::vector<ContactEvent>& run, RunErrors& e) const;
  const ReferenceTrace& ref_;
  double horizon_s_;
  ImpulseWindows windows_;
  std::vector<ContactEvent> events_;
  RunErrors e_;
  double sum_rotor2_ = 0.0, sum_stator2_ = 0.0;
  double last_t_s_ = 0.0;
  bool last_in_contact_ = false;
  bool last_sticking_ = false;
};

}  // namespace rotor_rub::core
