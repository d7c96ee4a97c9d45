#include "rotor_rub_sim/core/run_errors.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "rotor_rub_sim/core/trajectory_compare.hpp"

namespace rotor_rub::core {

void ImpulseWindows::add(std::size_t k, double impulse_N_s) {
  if (k >= impulse_.size()) {
    impulse_.resize(k + 1, 0.0);
    contact_.resize(k + 1, false);
  }
  impulse_[k] += impulse_N_s;
}

void ImpulseWindows::mark(std::size_t k) {
  add(k, 0.0);
  contact_[k] = true;
}

void ImpulseWindows::add_sample(double t_s, double normal_force_N, bool in_contact) {
  const auto window_of = [this](double t) { return static_cast<std::size_t>(std::floor(t / window_s_ + 1e-9)); };
  if (in_contact) mark(window_of(t_s));
  if (have_last_) {
    // Trapezoid from the last sample to this one, split at window edges.
    double t0 = last_t_s_, f0 = last_f_N_;
    const double slope = (normal_force_N - last_f_N_) / (t_s - last_t_s_);
    while (t0 < t_s) {
      const std::size_t k = window_of(t0);
      const double edge = std::min(t_s, static_cast<double>(k + 1) * window_s_);
      const double t1 = edge > t0 ? edge : t_s;
      const double f1 = last_f_N_ + slope * (t1 - last_t_s_);
      add(k, 0.5 * (f0 + f1) * (t1 - t0));
      t0 = t1;
      f0 = f1;
    }
  } else {
    add(window_of(t_s), 0.0);
  }
  have_last_ = true;
  last_t_s_ = t_s;
  last_f_N_ = normal_force_N;
}

void ImpulseWindows::add_event(const ContactEvent& e) {
  const auto k = static_cast<std::size_t>(std::floor(e.t_s / window_s_));
  mark(k);
  add(k, e.impulse_N_s);
}

namespace {

struct TraceObserver : SimulationObserver {
  ReferenceTrace* trace;
  void on_sample(const Sample& s) override {
    trace->t_s.push_back(s.t_s);
    trace->rotor_pos_m.push_back(s.kin.rotor_pos);
    trace->stator_pos_m.push_back(s.kin.stator_pos);
    trace->windows.add_sample(s.t_s, s.normal_force_N, s.in_contact);
  }
  void on_event(const ContactEvent& e) override {
    trace->events.push_back(e);
    trace->windows.add_event(e);
  }
};

}  // namespace

ReferenceTrace record_reference(const Scene& scene, double window_s) {
  ReferenceTrace trace;
  trace.windows = ImpulseWindows(window_s);
  TraceObserver obs;
  obs.trace = &trace;
  const RunResult r = run_scene(scene, obs);
  if (r.failure) {
    trace.failed = true;
    trace.failure_message = r.failure->message;
  }
  return trace;
}

double sensitivity_horizon_s(const ReferenceTrace& reference, const ReferenceTrace& witness, double apart_m) {
  const std::size_t n = std::min(reference.t_s.size(), witness.t_s.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (!((witness.rotor_pos_m[i] - reference.rotor_pos_m[i]).norm() <= apart_m)) return reference.t_s[i];
  }
  if (witness.failed && n > 0) return witness.t_s[n - 1];
  return std::numeric_limits<double>::infinity();
}

void ErrorObserver::on_sample(const Sample& s) {
  const std::size_t i = e_.samples;
  if (i >= ref_.t_s.size()) return;  // the reference failed earlier: compare the common prefix
  if (std::abs(s.t_s - ref_.t_s[i]) > 1e-12) {
    throw std::invalid_argument("ErrorObserver: the run is not sampled on the reference's grid");
  }
  const double dr = (s.kin.rotor_pos - ref_.rotor_pos_m[i]).norm();
  const double ds = (s.kin.stator_pos - ref_.stator_pos_m[i]).norm();
  e_.max_rotor_m = std::max(e_.max_rotor_m, dr);
  if (s.t_s < horizon_s_) e_.max_rotor_in_horizon_m = std::max(e_.max_rotor_in_horizon_m, dr);
  e_.max_stator_m = std::max(e_.max_stator_m, ds);
  sum_rotor2_ += dr * dr;
  sum_stator2_ += ds * ds;
  e_.max_orbit_m = std::max(e_.max_orbit_m, s.kin.rotor_pos.norm());
  e_.peak_normal_force_N = std::max(e_.peak_normal_force_N, s.normal_force_N);
  if (i > 0 && last_in_contact_) e_.contact_time_s += s.t_s - last_t_s_;
  if (i > 0 && last_sticking_) e_.stick_time_s += s.t_s - last_t_s_;
  last_t_s_ = s.t_s;
  last_in_contact_ = s.in_contact;
  last_sticking_ = s.sticking;
  windows_.add_sample(s.t_s, s.normal_force_N, s.in_contact);
  ++e_.samples;
}

void ErrorObserver::compare_events(const std::vector<ContactEvent>& run, RunErrors& e) const {
  const auto contact_changes = [this](const std::vector<ContactEvent>& events) {
    std::vector<ContactEvent> out;
    for (const auto& ev : events) {
      if (ev.t_s < horizon_s_) out.push_back(ev);
    }
    return out;
  };
  const auto a = contact_changes(run), b = contact_changes(ref_.events);
  // A failed run is compared over what it ran.
  const double ran_to_s = e_.samples > 0 ? last_t_s_ : 0.0;
  e.max_event_err_s = 0.0;
  e.event_mismatch_s = std::numeric_limits<double>::quiet_NaN();
  std::size_t k = 0;
  for (; k < b.size() && b[k].t_s <= ran_to_s; ++k) {
    if (k >= a.size() || a[k].kind != b[k].kind || std::abs(a[k].t_s - b[k].t_s) > windows_.window_s()) {
      e.event_mismatch_s = b[k].t_s;
      return;
    }
    e.max_event_err_s = std::max(e.max_event_err_s, std::abs(a[k].t_s - b[k].t_s));
  }
  // Every reference event the run reached agrees: one more of the run's is in excess.
  if (k < a.size()) e.event_mismatch_s = a[k].t_s;
}

void ErrorObserver::on_event(const ContactEvent& e) {
  events_.push_back(e);
  windows_.add_event(e);
}

RunErrors ErrorObserver::finish() const {
  RunErrors e = e_;
  const double n = static_cast<double>(std::max<std::size_t>(e.samples, 1));
  e.rms_rotor_m = std::sqrt(sum_rotor2_ / n);
  e.rms_stator_m = std::sqrt(sum_stator2_ / n);
  e.first_contact_s = first_contact_s(events_);
  e.first_contact_err_s = e.first_contact_s - first_contact_s(ref_.events);
  e.last_contact_end_s = last_contact_end_s(events_);
  e.last_contact_end_err_s = e.last_contact_end_s - last_contact_end_s(ref_.events);
  compare_events(events_, e);

  const auto& ri = ref_.windows.impulse_N_s();
  const auto& rc = ref_.windows.in_contact();
  const auto& mi = windows_.impulse_N_s();
  double peak = 0.0;
  for (double v : ri) peak = std::max(peak, v);
  e.ref_peak_window_force_N = peak / ref_.windows.window_s();
  // Windows the run covered completely (a failed run stops early).
  const std::size_t covered = std::min(ri.size(), mi.size() > 0 ? mi.size() - 1 : 0);
  std::size_t contact_windows = 0, within = 0;
  double worst = 0.0;
  for (std::size_t k = 0; k < covered; ++k) {
    if (!rc[k]) continue;
    ++contact_windows;
    const double rel = peak > 0.0 ? std::abs(mi[k] - ri[k]) / peak : 0.0;
    worst = std::max(worst, rel);
    if (rel <= 0.05) ++within;
  }
  e.impulse_window_err_rel = contact_windows ? worst : std::numeric_limits<double>::quiet_NaN();
  e.impulse_windows_within_5pct = contact_windows ? static_cast<double>(within) / static_cast<double>(contact_windows)
                                                  : std::numeric_limits<double>::quiet_NaN();
  return e;
}

}  // namespace rotor_rub::core
