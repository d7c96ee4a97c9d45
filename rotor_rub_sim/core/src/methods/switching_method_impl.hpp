// The switching method's class template and its factory, included by one
// unit per kind of rotor (switching_method_{jeffcott,flexible}.cpp: in one
// unit the build's longest compile, docs/testing.md); its unnamed namespace
// gives each unit its own copy (the registry calls each unit's factory).
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

#include "contact/angle_pair.hpp"
#include "methods/chatter_guard.hpp"
#include "methods/constrained_dynamics.hpp"
#include "methods/event_scanner.hpp"
#include "methods/method_factory.hpp"
#include "methods/switching_method.hpp"
#include "methods/switching_systems.hpp"
#include "rotor/rotor_model.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "run/cost_profiler.hpp"
#include "run/sample_builder.hpp"

namespace rotor_rub::core {
namespace {

// kScheme: the integrator key, each regime's by it (SwitchingIntegrators).
// Rotor: the rotor model (rotor_model.hpp); its block is carried through
// every regime and event unchanged (no impulse reaches it), but for a
// motor's spin jump's share at an impact.
template <int kStatorDof, bool kMotor, class Rotor, Integrator kScheme>
class SwitchingMethod final : public ContactMethod {
 public:
  using FL = FreeLayout<kStatorDof, kMotor, Rotor>;
  using CL = ContactLayout<kStatorDof, kMotor, Rotor>;
  using Integrators = SwitchingIntegrators<FL, CL, kScheme>;

  explicit SwitchingMethod(const Scene& scene)
      : rotor_(scene),
        model_(rotor_.adopt(scene.model)),
        free_int_(scene.solver.atol, scene.solver.rtol, scene.solver.min_step_s, scene.solver.max_steps),
        contact_int_(scene.solver.atol, scene.solver.rtol, scene.solver.min_step_s, scene.solver.max_steps),
        initial_step_s_(scene.solver.initial_step_s),
        penetration_tolerance_m_(scene.solver.atol),
        guard_(scene.solver.max_events_per_ms) {
    free_sys_.model = &model_;
    contact_sys_.dynamics.model = &model_;
    free_sys_.rotor = contact_sys_.dynamics.rotor = &rotor_;
    if (scene.solver.profile_cost) {
      free_sys_.rhs_time_s = contact_sys_.rhs_time_s = &stats_.rhs_time_s;
      event_time_s_ = &stats_.event_time_s;
      restart_time_s_ = &stats_.restart_time_s;
    }
  }

  void start(double t_s, const Kinematics& k, const SpeedSegment& segment) override {
    start_from(t_s, k, segment, ModalState::Zero(2 * rotor_.modal_size()));  // at rest
  }
  void start_with_modes(double t_s, const Kinematics& k, const SpeedSegment& segment,
                        const ModalState& modal) override {
    rotor_.check_block(modal);
    start_from(t_s, k, segment, modal);
  }
  void start_from(double t_s, const Kinematics& k, const SpeedSegment& segment, const ModalState& modal) {
    end_sample_valid_ = false;
    free_sys_.segment = contact_sys_.segment = segment;
    regime_ = Regime::kFree;
    pending_.due = false;
    pending_.modal = modal;
    enter_free(t_s, k, initial_step_s_);
  }

  void change_segment(double t_s, const SpeedSegment& segment) override {
    end_sample_valid_ = false;
    ProfileScope scope(restart_time_s_);
    // RODASP's step taken again to end here, under the old drive; not at an
    // event, whose state is on its surface: taken again, a graze fired again
    // (FlexibleRotorRuns.SwitchingOnRosenbrock4RunsTheRingingSealRub).
    if (regime_ == Regime::kFree) end_step_if_implicit(free_int_, free_sys_, t_s, stats_);
    free_sys_.segment = contact_sys_.segment = segment;
    ++stats_.restarts;
    if (pending_.due) {
      // An event exactly here carries over (the state at an instant does not
      // depend on the drive ahead); one later in the step was found under the
      // old drive and is dropped (the caller drops its report).
      if (pending_.t_s <= t_s) return;
      pending_.due = false;
    }
    if (regime_ == Regime::kFree) {
      const typename FL::State x = free_state(t_s);
      const double dt = free_int_.dt();
      free_int_.initialize(free_sys_, x, t_s, dt, stats_);
    } else {
      const typename CL::State x = contact_state(t_s);
      const double dt = contact_int_.dt();
      contact_int_.initialize(contact_sys_, x, t_s, dt, stats_);
    }
    // The contact forces jump with the drive (m e A and A R_r terms in the
    // stick force and F_n), so an event function can jump across zero here:
    // the arming carries over, the next step() fires such a jump at t_s.
    values_end_ = event_values(t_s);
    valid_begin_ = valid_end_ = t_s;
  }

  void change_model(double t_s, const ModelParameters& p, std::vector<ContactEvent>& events) override {
    end_sample_valid_ = false;
    ProfileScope scope(restart_time_s_);
    if (pending_.due) {
      // An event exactly here has happened (the state at t_s is its new
      // regime's); one later in the step was found under the old model.
      if (pending_.t_s <= t_s) {
        apply_pending();
      } else {
        pending_.due = false;
      }
    }
    Kinematics k;
    const bool was_stick = regime_ == Regime::kContact && contact_sys_.dynamics.mode.stick;
    if (regime_ == Regime::kFree) {
      end_step_if_implicit(free_int_, free_sys_, t_s, stats_);  // as at a segment's end
      const typename FL::State x = free_state(t_s);
      k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
      pending_.modal = modal_of<FL>(x);
    } else {
      const typename CL::State x = contact_state(t_s);
      k = contact_sys_.dynamics.kinematics(x);
      pending_.modal = modal_of<CL>(x);
    }
    const Vec2 old_frame = model_.frame_shift();
    model_ = StationModel(rotor_.adopt(p));
    k.rotor_pos += old_frame - model_.frame_shift();
    pending_.due = true;
    pending_.t_s = t_s;
    pending_.kin = k;
    pending_.regime = Regime::kFree;
    if (regime_ == Regime::kContact) {
      const DriveState d = free_sys_.segment.at(t_s);
      const ContactGeometry g = model_.contact_geometry(k, model_.drive_at(k, d));
      if (g.penetration_m >= -penetration_tolerance_m_) {
        typename CL::State x = contact_sys_.dynamics.reduce(k, pending_.modal);
        const auto c = contact_sys_.dynamics.evaluate(x, d);
        if (c.normal_force_N > 0.0) {
          pending_.regime = Regime::kContact;
          pending_.mode =
              select_friction_mode(c.sliding_velocity_m_per_s, was_stick || !model_.has_friction(), c.stick_force_N,
                                   model_.parameters().friction_coefficient * c.stick_normal_force_N);
          if (pending_.mode.stick != was_stick) ++stats_.friction_transitions;
          pending_.contact_state = x;
        }
      }
      if (pending_.regime == Regime::kFree) events.push_back({t_s, EventKind::kLiftoff, 0.0, 0.0});
    }
    apply_pending();  // the restart, counted there
  }

  void step(double t_limit_s, std::vector<ContactEvent>& events) override {
    end_sample_valid_ = false;
    if (pending_.due) {
      ProfileScope scope(restart_time_s_);
      apply_pending();
    }
    if (regime_ == Regime::kContact) {
      // An armed function already on its far side at the step's start
      // jumped there at a drive change: its event is now (a zero-length step).
      for (int k = 0; k < kEventFunctions; ++k) {
        if (watch_[k].armed && values_end_.value[k] >= 0.0) {
          valid_begin_ = valid_end_;
          on_event(static_cast<EventFunction>(k), valid_end_, events);
          return;
        }
      }
    }
    if (regime_ == Regime::kFree) {
      free_int_.do_step(free_sys_, stats_);
      scan(free_int_.t_old(), std::min(free_int_.t_new(), t_limit_s), events);
    } else {
      contact_int_.limit_dt(Integrators::kContactScanPoints * kMaxScanAngle_rad /
                            std::abs(values_end_.forcing_rate_rad_per_s));
      contact_int_.do_step(contact_sys_, stats_);
      scan(contact_int_.t_old(), std::min(contact_int_.t_new(), t_limit_s), events);
      record_contact_quality(valid_end_);
    }
  }

  double step_begin() const override { return valid_begin_; }
  double step_end() const override { return valid_end_; }

  // The step end's sample is asked for twice (the contact quality record, the loop's invariant check): kept
  // from the first time until the method changes (a contact sample costs a constrained-dynamics evaluation).
  Sample sample(double t_s) const override {
    if (end_sample_valid_ && t_s == end_sample_.t_s) return end_sample_;
    return compute_sample(t_s);
  }

  const FlexibleRotorModel* flexible_rotor() const override { return rotor_.flexible(); }
  void change_rotor(double t_s, std::shared_ptr<const FlexibleRotorModel> rotor) override {
    if (regime_ == Regime::kFree) end_step_if_implicit(free_int_, free_sys_, t_s, stats_);  // under the old rotor
    rotor_.replace(std::move(rotor));
  }
  ModalState modal_state(double t_s) const override {
    if (rotor_.modal_size() == 0) return ModalState();  // no block: nothing to interpolate
    return regime_ == Regime::kFree ? modal_of<FL>(free_state(t_s)) : modal_of<CL>(contact_state(t_s));
  }

  const RunStats& stats() const override { return stats_; }
  RunStats& mutable_stats() override { return stats_; }

 private:
  // The sample at t_s, finished by the rotor (a flexible rotor's probe readings and drive torque: finish_sample).
  Sample compute_sample(double t_s) const {
    Vec2 unbalance_dir;
    Sample s = station_sample(t_s, unbalance_dir);
    rotor_.finish_sample(model_, modal_state(t_s), unbalance_dir, s);
    return s;
  }

  // The station's sample at t_s, and the unbalance's direction there (a
  // contact sample's from its evaluation, not computed twice).
  Sample station_sample(double t_s, Vec2& unbalance_dir) const {
    const DriveState reference = free_sys_.segment.at(t_s);
    if (regime_ == Regime::kFree) {
      const typename FL::State x = free_state(t_s);
      const Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
      const DriveState d = model_.drive_at(k, reference);
      const auto loads = motor_loads(k, d, modal_of<FL>(x));
      unbalance_dir = loads ? loads->unbalance_dir : model_.unbalance_dir(d.angle_rad);
      return make_sample(model_, t_s, k, d, model_.contact_geometry(k, d), 0.0, 0.0, false, loads ? &*loads : nullptr);
    }
    const typename CL::State x = contact_state(t_s);
    const auto c = contact_sys_.dynamics.evaluate(x, reference);
    const DriveState d = model_.drive_at(c.kin, reference);
    const auto loads = motor_loads(c.kin, d, modal_of<CL>(x));
    unbalance_dir = c.unbalance_dir;
    if (pending_.due && pending_.regime == Regime::kFree && t_s >= pending_.t_s) {
      // The located lift-off: F_n is zero there to the root's resolution
      // (the located time lies on the far side, where F_n = -O(1e-13) N).
      return make_sample(model_, t_s, c.kin, d, model_.contact_geometry(c.kin, d), 0.0, 0.0, true,
                         loads ? &*loads : nullptr);
    }
    if (pending_.due && t_s >= pending_.t_s) {
      // A friction transition at this instant: the sample reports the new
      // regime's forces (a stick force that jumped out of the cone at a drive
      // change is not applied, the slip force is).
      ConstrainedDynamics<kStatorDof, kMotor, Rotor> next = contact_sys_.dynamics;
      next.mode = pending_.mode;
      const auto cn = next.evaluate(x, reference);  // the reference: evaluate() applies the drive itself
      Sample s = make_sample(model_, t_s, cn.kin, d, model_.contact_geometry(cn.kin, d), cn.normal_force_N,
                             cn.tangential_force_N, true, loads ? &*loads : nullptr);
      s.sticking = pending_.mode.stick;
      return s;
    }
    Sample s = make_sample(model_, t_s, c.kin, d, model_.contact_geometry(c.kin, d), c.normal_force_N,
                           c.tangential_force_N, true, loads ? &*loads : nullptr);
    s.sticking = contact_sys_.dynamics.mode.stick;
    return s;
  }

  // The rotor's free loads under a motor drive (a sample's spin
  // acceleration takes a block's coupling in); none for the prescribed drive.
  std::optional<FreeLoads> motor_loads(const Kinematics& k, const DriveState& d, const ModalState& modal) const {
    if constexpr (kMotor) {
      return loads_at(rotor_, model_, k, d, modal);
    } else {
      return std::nullopt;
    }
  }

  static constexpr double kUnused = -std::numeric_limits<double>::infinity();

  EventValues event_values(double t_s) const {
    EventValues v;
    v.value.fill(kUnused);
    v.rate.fill(std::numeric_limits<double>::quiet_NaN());
    const DriveState d = free_sys_.segment.at(t_s);
    if (regime_ == Regime::kFree) {
      const typename FL::State x = free_state(t_s);
      const Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
      const ContactGeometry g = model_.contact_geometry(k, model_.drive_at(k, d));
      v.value[kGap] = g.penetration_m;
      v.rate[kGap] = g.normal_velocity_m_per_s;
      return v;
    }
    const typename CL::State x = contact_state(t_s);
    const auto& dynamics = contact_sys_.dynamics;
    const auto c = dynamics.evaluate(x, d);
    const double f = model_.parameters().friction_coefficient;
    v.forcing_rate_rad_per_s = c.drive.speed_rad_per_s - x[CL::kAngleRate];
    v.value[kGap] = -c.normal_force_N;
    if (dynamics.mode.stick) {
      v.value[kBreakaway] = std::abs(c.stick_force_N) - f * c.normal_force_N;
    } else if (model_.has_friction()) {
      v.value[kSlipEnd] = -dynamics.mode.slip_sign * c.sliding_velocity_m_per_s;
      v.rate[kSlipEnd] = -dynamics.mode.slip_sign * c.sliding_acc_m_per_s2;
    }
    if constexpr (!kMotor) {
      // The forces' rates in closed form (a motor's: differenced in crossing()).
      typename Rotor::ModalVector modal_jerk(rotor_.modal_size());
      const auto q = dynamics.force_rates(x, c, d, modal_jerk);
      v.rate[kGap] = -q.normal_N_per_s;
      if (dynamics.mode.stick) {
        v.rate[kBreakaway] = std::copysign(1.0, c.stick_force_N) * q.stick_N_per_s - f * q.normal_N_per_s;
      }
    }
    return v;
  }
  double event_value(int k, double t_s) const { return event_values(t_s).value[k]; }

  // The earliest event of [t0, t1], checked at the regime's scan points and
  // located on the dense output: a sign change of an armed function, the
  // deflated bracket right after a start on the surface, a crossing and back
  // between two points (crossing(), event_scanner.hpp).
  void scan(double t0, double t1, std::vector<ContactEvent>& events) {
    ProfileScope scope(event_time_s_);
    valid_begin_ = t0;
    double prev_t = t0;
    EventValues prev = values_end_;
    // A rebound's return (return_s_) inside the first interval: one more
    // point past it and before the interval's end, so that the flight and
    // its return never both fall between two points.
    const int points = scan_points_now();
    const double first_point = t0 + (t1 - t0) / points;
    const double probe_s = return_s_ + 0.5 * std::min(return_s_ - t0, first_point - return_s_);
    const bool probe = t0 == regime_start_s() && return_s_ > t0 && return_s_ < first_point && probe_s > t0;
    for (int i = probe ? 0 : 1; i <= points; ++i) {
      const double ti = i == 0 ? probe_s : scan_point(t0, t1, i, points);
      const EventValues cur = event_values(ti);
      double first_t = std::numeric_limits<double>::infinity();
      int first_k = -1;
      for (int k = 0; k < kEventFunctions; ++k) {
        if (cur.value[k] == kUnused) continue;
        const double te = crossing_of(k, prev_t, prev, ti, cur);
        if (te < first_t) {
          first_t = te;
          first_k = k;
        }
      }
      // Free flight that has not opened the gap since the switch (a graze at
      // the tangency, the pressing force just changing sign), yet penetrates:
      // contact where the penetration reaches the tolerance (the paper's
      // remedy for the stall, located, not at the step's end). The threshold
      // counts from the flight's start: never again at its own start.
      const double tol = penetration_tolerance_m_ + std::max(0.0, start_gap_m_);
      if (first_k < 0 && !watch_[kGap].armed && regime_ == Regime::kFree && cur.value[kGap] > tol &&
          (prev.value[kGap] < tol || prev_t > regime_start_s())) {
        auto beyond = [this, tol](double t) { return event_value(kGap, t) - tol; };
        first_t = prev.value[kGap] < tol
                      ? locate_event(beyond, prev_t, prev.value[kGap] - tol, ti, cur.value[kGap] - tol, stats_)
                      : prev_t;
        first_k = kGap;
      }
      if (first_k >= 0) {
        valid_end_ = first_t;
        on_event(static_cast<EventFunction>(first_k), first_t, events);
        return;
      }
      for (int k = 0; k < kEventFunctions; ++k) {
        if (cur.value[k] < 0.0 && cur.value[k] != kUnused) watch_[k].armed = true;
      }
      prev_t = ti;
      prev = cur;
    }
    valid_end_ = t1;
    values_end_ = prev;
  }

  // The crossing time of function k in [a, b], or +infinity (event_scanner.hpp);
  // without rates in closed form (a motor's contact forces), differenced.
  double crossing_of(int k, double a, const EventValues& va, double b, const EventValues& vb) {
    auto f = [this, k](double t) { return event_value(k, t); };
    auto rate = [this, k](double t) { return event_values(t).rate[k]; };
    return crossing(watch_[k], f, rate, a, va.value[k], va.rate[k], b, vb.value[k], vb.rate[k], stats_);
  }

  void on_event(EventFunction k, double te, std::vector<ContactEvent>& events) {
    guard_.record(te);
    pending_.from_breakaway = pending_.quiet = false;
    const DriveState d = free_sys_.segment.at(te);
    pending_.t_s = te;
    pending_.due = true;
    if (regime_ == Regime::kContact) {
      const typename CL::State x = contact_state(te);
      if (k == kGap) {
        events.push_back({te, EventKind::kLiftoff, 0.0, 0.0});
        pending_.kin = contact_sys_.dynamics.kinematics(x);
        pending_.modal = modal_of<CL>(x);
        pending_.regime = Regime::kFree;
        return;
      }
      // A friction transition: slip to stick or reversal at v_slide = 0, or
      // stick to slip at the cone's edge. The contact goes on.
      ++stats_.friction_transitions;
      const auto c = contact_sys_.dynamics.evaluate(x, d);
      const double cone = model_.parameters().friction_coefficient * c.stick_normal_force_N;
      if (k == kSlipEnd) {
        pending_.mode = select_friction_mode(0.0, true, c.stick_force_N, cone);
      } else {
        pending_.mode.stick = false;
        pending_.mode.slip_sign = c.stick_force_N > 0.0 ? -1.0 : 1.0;
        pending_.from_breakaway = true;
      }
      pending_.contact_state = x;
      pending_.regime = Regime::kContact;
      return;
    }
    const typename FL::State x_at = free_state(te);
    Kinematics k_at = kinematics_of<kStatorDof, kMotor, Rotor>(x_at);
    pending_.modal = modal_of<FL>(x_at);
    const DriveState d_at = model_.drive_at(k_at, d);
    const ContactGeometry g = model_.contact_geometry(k_at, d_at);
    ContactEvent e;
    e.t_s = te;
    bool settles = true, at_rest = false;
    const bool closing = closes(g, k_at);
    if (closing) {
      const FreeLoads free = loads_at(rotor_, model_, k_at, d_at, pending_.modal);
      const ImpactResult ir = apply_impact(model_, g, d_at, penetration_tolerance_m_, free, k_at);
      // A motor's spin jumps with the impact, and the block with it (dxi' = h_xi dw).
      if constexpr (kMotor) {
        rotor_.add_spin_share(free.unbalance_dir, ir.spin_jump_rad_per_s, pending_.modal.tail(rotor_.modal_size()));
      }
      settles = ir.settles;
      at_rest = ir.sliding_stopped;
      e.normal_velocity_m_per_s = ir.closing_velocity_m_per_s;
      e.impulse_N_s = ir.normal_impulse_N_s;
    }
    pending_.kin = k_at;
    bool sustained = false;
    if (settles) {
      typename CL::State x = contact_sys_.dynamics.reduce(k_at, pending_.modal);
      const auto c = contact_sys_.dynamics.evaluate(x, d);
      sustained = c.normal_force_N > 0.0;
      if (sustained) {
        pending_.mode =
            select_friction_mode(c.sliding_velocity_m_per_s, at_rest || !model_.has_friction(), c.stick_force_N,
                                 model_.parameters().friction_coefficient * c.stick_normal_force_N);
        pending_.contact_state = x;
      }
    }
    pending_.regime = sustained ? Regime::kContact : Regime::kFree;
    // At the bore, neither closing (closes(), contact_law.hpp) nor pressed:
    // no contact, as in the iteration method; the flight restarts unrecorded
    // (the gap's rounding after a lift-off; a loose dense output's, below).
    pending_.quiet = !sustained && !closing;
    if (pending_.quiet) return;
    e.kind = sustained ? EventKind::kTouchdown : EventKind::kGraze;
    events.push_back(e);
  }

  void apply_pending() {
    pending_.due = false;
    ++stats_.restarts;
    double dt = regime_ == Regime::kFree ? free_int_.dt() : contact_int_.dt();
    // A loose dense output need not move the position as its velocity says: on a long carried step the
    // position crept beyond the bore, quiet restart after restart (LooseTolerance.*). Such a flight, every
    // flight on RODASP (whose output need not leave a step's start along the velocity) and dop853's contact
    // after RODASP's flight (RODASP's step knows nothing of dop853's stability:
    // LargeRotor.SwitchingOnRosenbrock4TouchesDownAfterALongFlight) begin with the first trial step.
    const bool afresh =
        std::exchange(pending_.quiet, false) || scheme_next<kScheme>(free_int_) == Integrator::kRosenbrock4;
    const bool from_rodasp = regime_ == Regime::kFree && scheme_now<kScheme>(free_int_) == Integrator::kRosenbrock4;
    if ((afresh && pending_.regime == Regime::kFree) || from_rodasp) dt = std::min(dt, initial_step_s_);
    if (pending_.regime == Regime::kFree) {
      regime_ = Regime::kFree;
      enter_free(pending_.t_s, pending_.kin, dt);
      return;
    }
    regime_ = Regime::kContact;
    contact_sys_.dynamics.mode = pending_.mode;
    typename CL::State x = pending_.contact_state;
    if (pending_.mode.stick) {
      // Rolling: v_slide = C psi' + w R_r = 0 exactly.
      const double w = contact_sys_.dynamics.spin_speed(x, contact_sys_.segment.at(pending_.t_s));
      x[CL::kAngleRate] = -w * model_.parameters().rotor_radius_m / model_.parameters().clearance_m;
    }
    contact_int_.initialize(contact_sys_, x, pending_.t_s, dt, stats_);
    begin_regime(pending_.t_s, pending_.from_breakaway);
    pending_.from_breakaway = false;
  }

  // From k and the modal block pending_.modal.
  void enter_free(double t_s, const Kinematics& k, double dt) {
    typename FL::State x = sized_state<FL>(pending_.modal);
    store_kinematics<kStatorDof, kMotor, Rotor>(k, x);
    free_int_.initialize(free_sys_, x, t_s, dt, stats_);
    begin_regime(t_s);
  }

  // Every function of the new regime starts unarmed unless already strictly
  // on its own side; on its surface with a rate into its side, the deflated
  // bracket (scan()) finds a crossing right after the start (a slip begun at
  // a breakaway has no such rate: crossing()).
  void begin_regime(double t_s, bool slip_from_breakaway = false) {
    values_end_ = event_values(t_s);
    start_gap_m_ = regime_ == Regime::kFree ? values_end_.value[kGap] : 0.0;
    for (int k = 0; k < kEventFunctions; ++k) {
      const double value = values_end_.value[k], rate = values_end_.rate[k];
      EventWatch& w = watch_[k];
      w.armed = value < 0.0 && value != kUnused;
      w.regime_start_s = t_s;
      w.on_surface = starts_on_surface(value, rate);
      w.start_rate = rate;
      w.on_surface_without_rate = k == kSlipEnd && slip_from_breakaway;
    }
    return_s_ = std::numeric_limits<double>::infinity();
    if (regime_ == Regime::kFree && watch_[kGap].on_surface) {
      // A rebound at v_n < 0 pressed back at a_press returns after about
      // 2 |v_n| / a_press (a parabola over so short a flight): scan() probes
      // past it, on the bore's far side if it returned
      // (ReboundCascade.EveryReturnIsFound).
      const typename FL::State x = free_state(t_s);
      const Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
      const DriveState d = model_.drive_at(k, free_sys_.segment.at(t_s));
      const ContactGeometry g = model_.contact_geometry(k, d);
      const double a_press = pressing_acceleration(model_, k, d, g, loads_at(rotor_, model_, k, d, modal_of<FL>(x)));
      if (a_press > 0.0) return_s_ = t_s + 2.0 * -values_end_.rate[kGap] / a_press;
    }
    valid_begin_ = valid_end_ = t_s;
  }

  void record_contact_quality(double t_s) {
    // The constraint holds by construction; record the sliding speed to show
    // how close the run comes to a friction transition.
    end_sample_ = compute_sample(t_s);
    end_sample_valid_ = true;
    const Sample& s = end_sample_;
    stats_.min_abs_sliding_velocity_m_per_s =
        std::min(stats_.min_abs_sliding_velocity_m_per_s, std::abs(s.sliding_velocity_m_per_s));
    stats_.max_constraint_violation_m = std::max(stats_.max_constraint_violation_m, std::abs(s.penetration_m));
  }

  // The dense output of the free regime's and the contact regime's integrator.
  typename FL::State free_state(double t_s) const {
    typename FL::State x;
    free_int_.state_at(t_s, x);
    return x;
  }
  typename CL::State contact_state(double t_s) const {
    typename CL::State x;
    contact_int_.state_at(t_s, x);
    return x;
  }
  int scan_points_now() const {
    return regime_ == Regime::kFree ? scan_points(scheme_now<kScheme>(free_int_)) : Integrators::kContactScanPoints;
  }
  Rotor rotor_;
  StationModel model_;  // the station (Rotor::adopt)
  FreeFlightSystem<kStatorDof, kMotor, Rotor> free_sys_;
  ContactSystem<kStatorDof, kMotor, Rotor> contact_sys_;
  typename Integrators::Free free_int_;
  typename Integrators::Contact contact_int_;
  double initial_step_s_;
  double penetration_tolerance_m_;
  ChatterGuard guard_;
  Regime regime_ = Regime::kFree;
  std::array<EventWatch, kEventFunctions> watch_{};  // each function since its regime began
  double regime_start_s() const { return watch_[0].regime_start_s; }
  double return_s_ = std::numeric_limits<double>::infinity();  // begin_regime(): a rebound's predicted return
  double start_gap_m_ = 0.0;  // the penetration a free flight starts with (<= 0 but at a graze)
  EventValues values_end_{};
  double valid_begin_ = 0.0, valid_end_ = 0.0;
  // The restart an event leaves due at its time (apply_pending), in the
  // regime it enters.
  struct PendingRestart {
    bool due = false;
    double t_s = 0.0;
    Regime regime = Regime::kFree;
    Kinematics kin;
    ModalState modal;  // with kin: the rotor's block (a flexible rotor's [xi; xi'])
    FrictionMode mode;
    bool from_breakaway = false;  // a slip that begins at a breakaway (begin_regime)
    bool quiet = false;           // at the bore, neither closing nor pressed (on_event)
    typename CL::State contact_state;
  };
  PendingRestart pending_;
  RunStats stats_;
  double* event_time_s_ = nullptr;    // profiling only
  double* restart_time_s_ = nullptr;  // profiling only
  Sample end_sample_;
  bool end_sample_valid_ = false;
};

template <Integrator kScheme, class Rotor>
struct SwitchingOn {
  template <int kStatorDof, bool kMotor>
  using Method = SwitchingMethod<kStatorDof, kMotor, Rotor, kScheme>;
};

// The method for a scene on one kind of rotor: the Jeffcott's (fixed-size
// states) or a flexible rotor's, each kind in its own translation unit
// (the classes keep the internal linkage the compiler inlines best).
template <Integrator I, class Rotor>
std::unique_ptr<ContactMethod> make_switching_for_rotor(const Scene& scene) {
  return make_for_scene<SwitchingOn<I, Rotor>::template Method>(scene);
}

}  // namespace
}  // namespace rotor_rub::core
