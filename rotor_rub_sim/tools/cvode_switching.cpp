#include "cvode_switching.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "cvode_integrator.hpp"
#include "methods/chatter_guard.hpp"
#include "methods/constrained_dynamics.hpp"
#include "methods/event_scanner.hpp"
#include "rotor/rotor_model.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/model.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"
#include "run/sample_builder.hpp"

namespace rotor_rub::tools {
namespace {

using core::ContactEvent;
using core::DriveState;
using core::EventKind;
using core::FrictionMode;
using core::Kinematics;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// A restart's first step: this share of the step CVODE would have taken next
// in the regime it leaves, as the core restarts with the step size it had.
// CVODE's own estimate bounds the step by 0.1 (|y_i| + atol) / |y_i'| per
// component, and a component that starts at zero (a normal velocity a
// plastic impact has just zeroed, a stator at rest) made it 5e-12 s after a
// graze. The whole step would not do either: the restart is at order 1, whose
// error constant is far larger than that of the order the step was chosen
// for; 0.1 is the cut CVODE itself makes after an error test failure.
// Against CVODE's own estimate: the same cost, and closer agreement with the
// core where impacts amplify differences (docs/benchmarks.md, "Timings the
// other pages rest on").
constexpr double kRestartStepFactor = 0.1;
// The gap's rounding: delta - C from positions of size |r_r| + |r_s| + C
// carries a few eps of that; this many eps of it is the noise floor below
// which the gap's sign means nothing (~6e-17 m on the paper scene).
constexpr double kGapNoiseEps = 64.0;

// ---- The switching method on CVODE ------------------------------------------

enum class Regime { kFree, kContact };

struct RootValues {
  std::array<double, kRoots> value{};
  std::array<double, kRoots> rate{kNaN, kNaN};  // d value / dt where known
};

// How each root function starts its regime.
// * A function that starts on its surface with a known rate into its own
//   side (a rebound, a slip from rest) is handed to CVODE deflated,
//   value / (t - t_start), whose value at t_start is that rate: CVODE sees it
//   strictly negative from the start, so the crossing back is found however
//   early it comes (the undeflated function starts at +0 and may return to +
//   within CVODE's first step, a sign change CVODE cannot see). The core does
//   the same (event_scanner.hpp, crossing()).
// * The free flight's gap must be seen below its noise floor before a
//   crossing counts (armed). CVODE arms on any negative value at a step end,
//   and a flight that starts at a tangency (after a lift-off, or a plastic
//   touch that does not stay: normal velocity 0, the gap opening as t^2 or
//   t^3) spends its first steps inside the gap's rounding, where the sign is
//   noise: CVODE then located spurious grazes (2 on the rolling scene, 6
//   within 2e-11 s on another run). The core arms at its scan points too,
//   but restarts with the step it had, long enough to leave the noise.
//   Until armed, CVODE gets min(gap, -noise): never a crossing, and equal to
//   the gap at the step end where it arms, so CVODE's stored value there
//   stays right. A flight that never opens the gap is kForcedGap's.
struct RootStart {
  double t_s = 0.0;
  std::array<bool, kRoots> deflated{};
  std::array<double, kRoots> rate{};
  double forced_gap_threshold_m = 0.0;
  double gap_noise_m = 0.0;
  bool gap_armed = true;
};

// Rotor: the core's rotor model (rotor_model.hpp, as its switching method
// takes it), its block (a flexible rotor's [xi; xi']) after each regime's
// fixed part, carried unchanged through every event (no contact force or
// impulse reaches it).
template <int kStatorDof, class Rotor>
class CvodeSwitching {
 public:
  using FL = core::FreeLayout<kStatorDof, false, Rotor>;
  using CL = core::ContactLayout<kStatorDof, false, Rotor>;
  using FreeState = typename FL::State;
  using ContactState = typename CL::State;

  CvodeSwitching(const core::Scene& scene, double sample_rate_hz, const CvodeOptions& options, SUNContext ctx,
                 CvodeRun& out)
      : scene_(scene),
        rotor_(scene),
        modal_size_(2 * rotor_.modal_size()),
        model_(rotor_.adopt(scene.model)),
        profile_(scene.speed),
        guard_(scene.solver.max_events_per_ms),
        sample_rate_hz_(sample_rate_hz),
        out_(out),
        free_(ctx, FL::kSize + modal_size_, free_rhs, free_roots, this, scene, options, &cvode_error_),
        contact_(ctx, CL::kSize + modal_size_, contact_rhs, contact_roots, this, scene, options, &cvode_error_) {
    dynamics_.model = &model_;
    dynamics_.rotor = &rotor_;
    if (sample_rate_hz_ > 0.0) {
      out_.samples.reserve(static_cast<std::size_t>(std::floor(scene.end_time_s * sample_rate_hz_)) + 1);
    }
  }

  void run() {
    next_segment(0.0);
    restart_step_s_ = 0.0;  // at rest, centred: CVODE's estimate is sound here
    // As the core's Simulation starts: the scene's initial state, the modes at rest.
    enter_free(0.0, core::StationModel(scene_.model).initial_kinematics(profile_.at(0.0)),
               core::ModalState::Zero(modal_size_));
    double t_s = 0.0;
    long calls = 0;
    while (t_s < scene_.end_time_s) {
      if (++calls > scene_.solver.max_steps) {
        throw core::MethodFailure(core::FailureClass::kStalled, t_s,
                                  "step budget of " + std::to_string(scene_.solver.max_steps) + " steps spent");
      }
      t_s = advance();
    }
    free_.harvest(out_);
    contact_.harvest(out_);
  }

 private:
  Integrator& active() { return regime_ == Regime::kFree ? free_ : contact_; }

  // One CVODE step (CV_ONE_STEP: every step comes back here, for the in-step
  // graze check and the samples), then what it ended on. Returns the time
  // the run has reached.
  double advance() {
    Integrator& it = active();
    double t_ret = 0.0;
    const int flag = CVode(it.mem(), stop_s_, it.y(), &t_ret, CV_ONE_STEP);
    if (flag < 0) throw CvodeError(describe_failure("CVode", flag, cvode_error_));
    if (flag == CV_ROOT_RETURN) {
      std::array<int, kRoots> found{};
      it.check(CVodeGetRootInfo(it.mem(), found.data()), "CVodeGetRootInfo");
      // Simultaneous roots: the lower index first, as the core's scan does
      // (the gap or lift-off before friction).
      const int k = found[0] != 0 ? 0 : 1;
      emit_samples(t_ret);
      on_event(k, t_ret, it.state());
      return t_ret;
    }
    if (regime_ == Regime::kFree) {
      const double te = after_free_step(t_ret, it.state());
      if (te < kInf) {
        emit_samples(te);
        on_event(kGap, te, it.state_at(te));
        return te;
      }
    } else if constexpr (!Rotor::kStationOnly) {
      const auto [k, te] = after_contact_step(t_ret);
      if (te < kInf) {
        emit_samples(te);
        on_event(k, te, it.state_at(te));
        return te;
      }
    }
    emit_samples(t_ret);
    if (flag == CV_TSTOP_RETURN && t_ret < scene_.end_time_s) change_segment(t_ret);
    return t_ret;
  }

  // ---- Right-hand sides and root functions (no allocation: fixed-size Eigen
  // states on the stack, mapped onto the N_Vectors' arrays) ----

  static int free_rhs(double t_s, N_Vector y, N_Vector ydot, void* data) {
    const auto& self = *static_cast<const CvodeSwitching*>(data);
    const FreeState x = self.free_state(N_VGetArrayPointer(y));
    Eigen::Map<Eigen::VectorXd> dxdt(N_VGetArrayPointer(ydot), x.size());
    const Kinematics k = core::kinematics_of<kStatorDof, false, Rotor>(x);
    const DriveState d = self.segment_.at(t_s);
    dxdt.template segment<2>(FL::kRotorPos) = k.rotor_vel;
    // The station's force and the block's rows (the core's FreeFlightSystem).
    const int n = core::modal_count<FL>(x);
    dxdt.segment(FL::kModal, n) = x.tail(n);
    dxdt.template segment<2>(FL::kRotorVel) =
        self.rotor_.station_force(self.model_, k, d, self.model_.unbalance_dir(d.angle_rad), x.tail(2 * n),
                                  dxdt.tail(n)) *
        self.model_.inv_rotor_mass();
    if constexpr (kStatorDof == 2) {
      dxdt.template segment<2>(FL::kStatorPos) = k.stator_vel;
      dxdt.template segment<2>(FL::kStatorVel) = self.model_.stator_free_force(k) * self.model_.inv_stator_mass();
    }
    return 0;
  }

  // Reduced coordinates (stator, contact angle psi): r_r = r_s + C n(psi), so
  // |r_r - r_s| = C holds exactly at every instant, by construction; nothing
  // drifts and nothing needs stabilising. That is stronger than Baumgarte
  // stabilisation, which only damps the drift of a constraint written on the
  // accelerations of the full coordinates.
  static int contact_rhs(double t_s, N_Vector y, N_Vector ydot, void* data) {
    const auto& self = *static_cast<const CvodeSwitching*>(data);
    const ContactState x = self.contact_state(N_VGetArrayPointer(y));
    ContactState dxdt;
    self.dynamics_.derivative(x, self.segment_.at(t_s), dxdt);
    Eigen::Map<Eigen::VectorXd>(N_VGetArrayPointer(ydot), dxdt.size()) = dxdt;
    return 0;
  }

  static int free_roots(double t_s, N_Vector y, double* g, void* data) {
    const auto& self = *static_cast<const CvodeSwitching*>(data);
    self.deflate(self.free_values(self.free_state(N_VGetArrayPointer(y)), t_s), t_s, g);
    return 0;
  }

  static int contact_roots(double t_s, N_Vector y, double* g, void* data) {
    const auto& self = *static_cast<const CvodeSwitching*>(data);
    self.deflate(self.contact_values(self.contact_state(N_VGetArrayPointer(y)), t_s), t_s, g);
    return 0;
  }

  void deflate(const RootValues& v, double t_s, double* g) const {
    for (int k = 0; k < kRoots; ++k) {
      if (!start_.deflated[k]) {
        g[k] = v.value[k];
      } else {
        g[k] = t_s > start_.t_s ? v.value[k] / (t_s - start_.t_s) : start_.rate[k];
      }
    }
    if (regime_ == Regime::kFree && !start_.gap_armed) g[kGap] = std::min(v.value[kGap], -start_.gap_noise_m);
  }

  // A regime's state from CVODE's array (its size: the fixed part and the
  // modal block; fixed-size storage either way, no allocation).
  FreeState free_state(const double* y) const {
    FreeState x = Eigen::Map<const Eigen::VectorXd>(y, FL::kSize + modal_size_);
    return x;
  }
  ContactState contact_state(const double* y) const {
    ContactState x = Eigen::Map<const Eigen::VectorXd>(y, CL::kSize + modal_size_);
    return x;
  }

  RootValues free_values(const FreeState& x, double t_s) const {
    const Kinematics k = core::kinematics_of<kStatorDof, false, Rotor>(x);
    const core::ContactGeometry g = model_.contact_geometry(k, segment_.at(t_s));
    RootValues v;
    v.value[kGap] = g.penetration_m;
    v.rate[kGap] = g.normal_velocity_m_per_s;
    v.value[kForcedGap] = g.penetration_m - start_.forced_gap_threshold_m;
    return v;
  }

  RootValues contact_values(const ContactState& x, double t_s) const {
    const auto c = dynamics_.evaluate(x, segment_.at(t_s));
    RootValues v;
    v.value[kLiftoff] = -c.normal_force_N;
    const FrictionMode& mode = dynamics_.mode;
    if (mode.stick) {
      v.value[kFriction] = std::abs(c.stick_force_N) - model_.parameters().friction_coefficient * c.normal_force_N;
    } else if (model_.has_friction()) {
      v.value[kFriction] = -mode.slip_sign * c.sliding_velocity_m_per_s;
      v.rate[kFriction] = -mode.slip_sign * c.sliding_acc_m_per_s2;
    } else {
      v.value[kFriction] = -1.0;  // frictionless: no friction regime to end
    }
    return v;
  }

  RootValues values_at_state(const double* y, double t_s) const {
    if (regime_ == Regime::kFree) return free_values(free_state(y), t_s);
    return contact_values(contact_state(y), t_s);
  }

  // ---- Events (what follows each: SwitchingMethod::on_event) ----

  void on_event(int k, double te, const double* y) {
    guard_.record(te);
    ++out_.events;
    restart_step_s_ = kRestartStepFactor * active().next_step_s();
    if (regime_ == Regime::kFree) {
      on_free_event(te, free_state(y));
    } else {
      on_contact_event(k, te, contact_state(y));
    }
  }

  // Touchdown or graze: the impact law, then sustained contact if the impact
  // settles and the constraint force presses.
  void on_free_event(double te, const FreeState& x) {
    const DriveState d = segment_.at(te);
    Kinematics k = core::kinematics_of<kStatorDof, false, Rotor>(x);
    const core::ModalState modal = core::modal_of<FL>(x);
    const core::ContactGeometry g = model_.contact_geometry(k, d);
    ContactEvent e;
    e.t_s = te;
    bool settles = true, at_rest = false;
    const bool closing = core::closes(g, k);
    if (closing) {
      const core::ImpactResult ir =
          core::apply_impact(model_, g, d, scene_.solver.atol, core::loads_at(rotor_, model_, k, d, modal), k);
      settles = ir.settles;
      at_rest = ir.sliding_stopped;
      e.normal_velocity_m_per_s = ir.closing_velocity_m_per_s;
      e.impulse_N_s = ir.normal_impulse_N_s;
    }
    if (settles) {
      const ContactState xc = dynamics_.reduce(k, modal);
      const auto c = dynamics_.evaluate(xc, d);
      if (c.normal_force_N > 0.0) {
        e.kind = EventKind::kTouchdown;
        out_.events_found.push_back(e);
        const double cone = model_.parameters().friction_coefficient * c.stick_normal_force_N;
        enter_contact(te, xc,
                      core::select_friction_mode(c.sliding_velocity_m_per_s, at_rest || !model_.has_friction(),
                                                 c.stick_force_N, cone));
        return;
      }
    }
    // Neither closing nor pressed: no contact (the core's methods), unrecorded.
    if (closing) {
      e.kind = EventKind::kGraze;
      out_.events_found.push_back(e);
    }
    enter_free(te, k, modal);
  }

  // Lift-off, or a friction transition (the contact goes on).
  void on_contact_event(int k, double te, const ContactState& x) {
    if (k == kLiftoff) {
      out_.events_found.push_back({te, EventKind::kLiftoff, 0.0, 0.0});
      enter_free(te, dynamics_.kinematics(x), core::modal_of<CL>(x));
      return;
    }
    const auto c = dynamics_.evaluate(x, segment_.at(te));
    FrictionMode next;
    if (dynamics_.mode.stick) {  // breakaway: slide against the stick force
      next.slip_sign = c.stick_force_N > 0.0 ? -1.0 : 1.0;
    } else {  // the sliding stopped: stick, or slide on the other way
      const double cone = model_.parameters().friction_coefficient * c.stick_normal_force_N;
      next = core::select_friction_mode(0.0, true, c.stick_force_N, cone);
    }
    enter_contact(te, x, next);
  }

  void enter_free(double t_s, const Kinematics& k, const core::ModalState& modal) {
    regime_ = Regime::kFree;
    FreeState x = core::sized_state<FL>(modal);
    core::store_kinematics<kStatorDof, false, Rotor>(k, x);
    Eigen::Map<Eigen::VectorXd>(free_.state(), x.size()) = x;
    restart(free_, t_s);
    begin_regime(t_s, free_.state());
  }

  void enter_contact(double t_s, ContactState x, const FrictionMode& mode) {
    regime_ = Regime::kContact;
    dynamics_.mode = mode;
    if (mode.stick) {
      // Rolling: v_slide = C psi' + w R_r = 0 exactly.
      const core::ModelParameters& p = model_.parameters();
      x[CL::kAngleRate] = -segment_.at(t_s).speed_rad_per_s * p.rotor_radius_m / p.clearance_m;
    }
    Eigen::Map<Eigen::VectorXd>(contact_.state(), x.size()) = x;
    restart(contact_, t_s);
    begin_regime(t_s, contact_.state());
  }

  // An event located at the drive's segment end (CVODE's stop time) was
  // found under the ending segment and carries over (as in the core); the
  // new regime starts under the next segment (CVODE refuses a stop time at
  // the start).
  void restart(Integrator& it, double t_s) {
    if (t_s >= stop_s_) next_segment(t_s);
    it.reinit(t_s, stop_s_, restart_step_s_, out_);
  }

  void next_segment(double t_s) {
    segment_ = profile_.segment_at(t_s);
    stop_s_ = std::min(profile_.next_break_after(t_s), scene_.end_time_s);
  }

  // Which root functions start deflated (RootStart), and the free flight's
  // forced-contact threshold, from the values at the regime's start.
  void begin_regime(double t_s, const double* y) {
    start_ = RootStart{};
    start_.t_s = t_s;
    contact_step_begin_s_ = t_s;
    if (regime_ == Regime::kFree) {
      const FreeState x = free_state(y);
      const Kinematics k = core::kinematics_of<kStatorDof, false, Rotor>(x);
      const RootValues free = free_values(x, t_s);
      start_.forced_gap_threshold_m = scene_.solver.atol + std::max(0.0, free.value[kGap]);
      start_.gap_noise_m = kGapNoiseEps * std::numeric_limits<double>::epsilon() *
                           (k.rotor_pos.norm() + k.stator_pos.norm() + model_.parameters().clearance_m);
      step_begin_ = {t_s, free.value[kGap], free.rate[kGap]};
    }
    const RootValues v = values_at_state(y, t_s);
    for (int k = 0; k < kRoots; ++k) {
      const double rate = v.rate[k];
      start_.deflated[k] = !(v.value[k] < 0.0) && core::starts_on_surface(v.value[k], rate);
      start_.rate[k] = rate;
    }
    if (regime_ == Regime::kFree) {
      // Deflated only if the rate leaves the noise within the window.
      start_.deflated[kGap] = start_.deflated[kGap] && -v.rate[kGap] * core::kOnSurface_s >= start_.gap_noise_m;
      start_.gap_armed = start_.deflated[kGap] || v.value[kGap] < -start_.gap_noise_m;
    }
  }

  // After a free-flight step ending at t1: the gap is armed where it is below
  // its noise floor (RootStart), and the core's third way to a touchdown
  // (event_scanner.hpp, crossing()) is checked: a touch that enters and
  // leaves the bore inside one step, the gap negative at both ends, where
  // CVODE sees no sign change. The gap's rate falls through zero in between
  // (a maximum); located on the dense output, and the gap there decides.
  // Returns the touchdown time, or infinity.
  double after_free_step(double t1, const double* y1) {
    const RootValues v1 = free_values(free_state(y1), t1);
    const GapAt begin = step_begin_;
    step_begin_ = {t1, v1.value[kGap], v1.rate[kGap]};
    const bool armed_at_begin = start_.gap_armed;
    start_.gap_armed = armed_at_begin || v1.value[kGap] < -start_.gap_noise_m;
    if (!(armed_at_begin && begin.gap_m < 0.0 && v1.value[kGap] < 0.0)) return kInf;
    core::RunStats located;
    auto values = [this](double t) { return free_values(free_state(free_.state_at(t)), t); };
    auto gap = [&values](double t) { return values(t).value[kGap]; };
    auto rate = [&values](double t) { return values(t).rate[kGap]; };
    core::EventWatch w;
    w.armed = true;
    const double te =
        core::crossing(w, gap, rate, begin.t_s, begin.gap_m, begin.rate, t1, v1.value[kGap], v1.rate[kGap], located);
    out_.root_evals += located.root_iterations;
    return te;
  }

  // A rotor's modes ring the normal force: between two step ends
  // where -F_n (sticking: |F_t| - f F_n too) is below zero it can rise
  // through zero and back (a grazing lift-off), a sign change CVODE's root
  // finding cannot see. Checked as the core checks between its scan points,
  // on the step's two halves (core::crossing). Returns the
  // earliest such event's root and time (infinity: none).
  std::pair<int, double> after_contact_step(double t1) {
    const double t0 = contact_step_begin_s_;
    contact_step_begin_s_ = t1;
    core::RunStats located;
    auto value = [this](int k, double t) { return contact_values(contact_state(contact_.state_at(t)), t).value[k]; };
    const double tm = 0.5 * (t0 + t1);
    std::pair<int, double> first{kLiftoff, kInf};
    for (const auto& [a, b] : {std::pair{t0, tm}, std::pair{tm, t1}}) {
      for (const int k : {kLiftoff, kFriction}) {
        if (k == kFriction && !dynamics_.mode.stick) continue;
        const double va = value(k, a), vb = value(k, b);
        if (!(va < 0.0 && vb < 0.0)) continue;
        auto g = [&value, k](double t) { return value(k, t); };
        core::EventWatch w;
        w.armed = true;
        const double te = core::crossing(w, g, a, va, b, vb, located);
        if (te < first.second) first = {k, te};
      }
      if (first.second < kInf) break;
    }
    out_.root_evals += located.root_iterations;
    return first;
  }

  // A drive segment ends at t_s (CVODE stopped there): the forces' m e A and
  // A R_r terms jump, so the integration restarts under the new segment, and
  // a root function that the jump carried from below zero to its far side is
  // an event now (the core's change_segment()).
  void change_segment(double t_s) {
    Integrator& it = active();
    const RootValues before = values_at_state(it.state(), t_s);
    next_segment(t_s);
    const RootValues after = values_at_state(it.state(), t_s);
    for (int k = 0; k < kRoots; ++k) {
      if (before.value[k] < 0.0 && after.value[k] >= 0.0) {
        on_event(k, t_s, it.state());
        return;
      }
    }
    it.reinit(t_s, stop_s_, kRestartStepFactor * it.next_step_s(), out_);
    contact_step_begin_s_ = t_s;
  }

  // ---- Samples (error runs only) ----

  void emit_samples(double t_limit_s) {
    if (!(sample_rate_hz_ > 0.0)) return;
    for (;;) {
      const double tk = static_cast<double>(next_sample_) / sample_rate_hz_;
      if (tk > t_limit_s || tk > scene_.end_time_s) return;
      out_.samples.push_back(sample_at(tk));
      ++next_sample_;
    }
  }

  core::Sample sample_at(double t_s) {
    const DriveState d = segment_.at(t_s);
    const double* y = active().state_at(t_s);
    core::Sample s;
    core::ModalState modal;
    core::Vec2 unbalance_dir;
    if (regime_ == Regime::kFree) {
      const FreeState x = free_state(y);
      s = core::make_sample(model_, t_s, core::kinematics_of<kStatorDof, false, Rotor>(x), d, 0.0, 0.0, false);
      modal = core::modal_of<FL>(x);
      unbalance_dir = model_.unbalance_dir(d.angle_rad);
    } else {
      const ContactState x = contact_state(y);
      const auto c = dynamics_.evaluate(x, d);
      s = core::make_sample(model_, t_s, c.kin, d, c.normal_force_N, c.tangential_force_N, true);
      s.sticking = dynamics_.mode.stick;
      modal = core::modal_of<CL>(x);
      unbalance_dir = c.unbalance_dir;
    }
    // The rotor finishes the sample (a flexible rotor's probes read their node).
    rotor_.finish_sample(model_, modal, unbalance_dir, s);
    return s;
  }

  struct GapAt {
    double t_s = 0.0, gap_m = 0.0, rate = 0.0;
  };

  const core::Scene& scene_;
  Rotor rotor_;
  int modal_size_;  // the block's entries (0: the Jeffcott)
  core::StationModel model_;
  core::SpeedProfile profile_;
  core::ConstrainedDynamics<kStatorDof, false, Rotor> dynamics_;
  core::ChatterGuard guard_;
  double sample_rate_hz_;
  CvodeRun& out_;
  std::string cvode_error_;
  Integrator free_, contact_;
  core::SpeedSegment segment_;
  double stop_s_ = 0.0;
  double restart_step_s_ = 0.0;  // the first step to try after the next restart
  Regime regime_ = Regime::kFree;
  RootStart start_;
  GapAt step_begin_;                   // the gap and its rate where the current step began
  double contact_step_begin_s_ = 0.0;  // where the current contact step began (flexible rotors)
  long next_sample_ = 0;
};

template <int kStatorDof, class Rotor>
void run_with(const core::Scene& scene, double sample_rate_hz, const CvodeOptions& options, CvodeRun& out) {
  const auto wall_start = std::chrono::steady_clock::now();
  try {
    const ContextOwner context;
    CvodeSwitching<kStatorDof, Rotor> method(scene, sample_rate_hz, options, context.ctx, out);
    method.run();
  } catch (const CvodeError& e) {
    out.failure = e.what();
  } catch (const core::MethodFailure& e) {
    char at[64];
    std::snprintf(at, sizeof at, " at t = %.9g s", e.time_s);
    out.failure = std::string(core::to_string(e.failure_class)) + at + ": " + e.what();
  }
  out.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
}

}  // namespace

CvodeRun run_cvode_switching(const core::Scene& scene, double sample_rate_hz, const CvodeOptions& options) {
  CvodeRun out;
  if (scene.model.drive_model != core::DriveModel::kPrescribed) {
    out.failure = "cvode contender: prescribed drive only";
    return out;
  }
  const bool rigid = scene.model.stator_model == core::StatorModel::kRigid;
  if (core::rotor_kind(scene) == core::RotorKind::kJeffcott) {
    rigid ? run_with<0, core::JeffcottRotor>(scene, sample_rate_hz, options, out)
          : run_with<2, core::JeffcottRotor>(scene, sample_rate_hz, options, out);
  } else {
    rigid ? run_with<0, core::FlexibleRotor>(scene, sample_rate_hz, options, out)
          : run_with<2, core::FlexibleRotor>(scene, sample_rate_hz, options, out);
  }
  return out;
}

}  // namespace rotor_rub::tools
