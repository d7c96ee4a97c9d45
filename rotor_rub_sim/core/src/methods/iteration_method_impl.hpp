// The iteration method's class template and its factory, included by one
// unit per kind of rotor (iteration_method_{jeffcott,flexible}.cpp: in one
// unit the build's longest compile, docs/testing.md); its unnamed namespace
// gives each unit its own copy (the registry calls each unit's factory).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>

#include "methods/chatter_guard.hpp"
#include "methods/contact_force_solver.hpp"
#include "methods/event_scanner.hpp"
#include "methods/iteration_method.hpp"
#include "methods/iteration_system.hpp"
#include "methods/method_factory.hpp"
#include "rotor/rotor_model.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "run/cost_profiler.hpp"
#include "run/sample_builder.hpp"

namespace rotor_rub::core {
namespace {

// kScheme: the integrator key, each regime's by it (IterationIntegrator).
// Rotor: the rotor model (rotor_model.hpp), every free load of the station
// its (loads()); its block goes through projections, impacts and restarts
// unchanged (no contact force or impulse reaches it; a motor's spin jump at
// an impact takes it along).
template <int kStatorDof, bool kMotor, class Rotor, Integrator kScheme>
class IterationMethod final : public ContactMethod {
 public:
  using L = FreeLayout<kStatorDof, kMotor, Rotor>;
  using State = typename L::State;
  using Dense = IterationIntegrator<L, kScheme>;  // each regime's dense-output integrator

  explicit IterationMethod(const Scene& scene)
      : rotor_(scene),
        model_(rotor_.adopt(scene.model)),
        solver_(&model_, scene.solver.iteration_force_rtol, static_cast<int>(scene.solver.iteration_max_iterations)),
        integrator_(scene.solver.atol, scene.solver.rtol, scene.solver.min_step_s, scene.solver.max_steps),
        min_step_s_(scene.solver.min_step_s),
        initial_step_s_(scene.solver.initial_step_s),
        gap_tolerance_m_(scene.solver.atol),
        guard_(scene.solver.max_events_per_ms) {
    system_.model = &model_;
    system_.rotor = &rotor_;
    system_.solver = &solver_;
    system_.iterations = &stats_.root_iterations;
    if (scene.solver.profile_cost) {
      system_.rhs_time_s = &stats_.rhs_time_s;
      system_.iteration_time_s = &stats_.iteration_time_s;
      event_time_s_ = &stats_.event_time_s;
      restart_time_s_ = &stats_.restart_time_s;
    }
  }

  void start(double t_s, const Kinematics& k, const SpeedSegment& segment) override {
    start_from(t_s, k, segment, ModalState::Zero(2 * rotor_.modal_size()));
  }
  void start_with_modes(double t_s, const Kinematics& k, const SpeedSegment& segment,
                        const ModalState& modal) override {
    rotor_.check_block(modal);
    start_from(t_s, k, segment, modal);
  }
  void start_from(double t_s, const Kinematics& k, const SpeedSegment& segment, const ModalState& modal) {
    system_.segment = segment;
    system_.engaged = false;
    pending_.due = false;
    restart_from(t_s, k, modal, initial_step_s_);
  }

  void change_segment(double t_s, const SpeedSegment& segment) override {
    ProfileScope scope(restart_time_s_);
    integrator_.end_free_step_at(system_, t_s, stats_);  // under the old drive
    system_.segment = segment;
    ++stats_.restarts;
    if (pending_.due) {
      pending_.due = false;
      // A restart due exactly here (projection, impact) carries over; one
      // later in the step was decided under the old drive and is dropped.
      if (pending_.t_s <= t_s) {
        apply(pending_);
        return;
      }
    }
    State x;
    integrator_.state_at(t_s, x);
    restart_from(t_s, kinematics_of<kStatorDof, kMotor, Rotor>(x), modal_of<L>(x), integrator_.dt());
  }

  void change_model(double t_s, const ModelParameters& p, std::vector<ContactEvent>& events) override {
    ProfileScope scope(restart_time_s_);
    ++stats_.restarts;
    if (pending_.due) {
      // A restart due exactly here has happened (the state at t_s is its
      // regime's); one later in the step was decided under the old model.
      pending_.due = false;
      if (pending_.t_s <= t_s) apply(pending_);
    }
    integrator_.end_free_step_at(system_, t_s, stats_);
    State x;
    integrator_.state_at(t_s, x);
    Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
    const ModalState modal = modal_of<L>(x);
    const bool was_stick = system_.engaged && system_.mode.stick;
    const Vec2 old_frame = model_.frame_shift();
    model_ = StationModel(rotor_.adopt(p));
    k.rotor_pos += old_frame - model_.frame_shift();
    if (system_.engaged) {
      const DriveState d = model_.drive_at(k, system_.segment.at(t_s));
      const ContactGeometry g = model_.contact_geometry(k, d);
      if (g.penetration_m >= -gap_tolerance_m_ && pressing_acceleration(model_, k, d, g, loads(k, modal, d)) > 0.0) {
        model_.project_onto_bore(g, k);
        const FrictionMode mode = mode_at(k, modal, d, was_stick || !model_.has_friction(), t_s);
        if (mode.stick != was_stick) ++stats_.friction_transitions;
        apply(Pending{true, t_s, k, modal, true, mode, true});
        return;
      }
      events.push_back({t_s, EventKind::kLiftoff, 0.0, 0.0});
      system_.engaged = false;
    }
    restart_from(t_s, k, modal, integrator_.dt());
  }

  void step(double t_limit_s, std::vector<ContactEvent>& events) override {
    if (pending_.due) {
      // Deferred from the last step, whose dense output served its samples.
      ProfileScope scope(restart_time_s_);
      pending_.due = false;
      apply(pending_);
    }
    // A held step turns phi - psi by at most kMaxScanAngle_rad per scan
    // interval, as switching's: longer, a breakaway out of the cone and back
    // fell between two points (LooseTolerance.*).
    if (system_.engaged) {
      const DenseState at = dense_state(valid_end_);
      integrator_.limit_dt(Dense::kEngagedScanPoints * kMaxScanAngle_rad / forcing_rate_rad_per_s(at.k, at.d, at.g));
    }
    for (;;) {
      integrator_.do_step(system_, stats_);
      if (system_.engaged) break;
      ProfileScope scope(event_time_s_);
      // Free step: reject it while it reaches beyond the bore by more than
      // the gap tolerance anywhere (no event location for touchdown in this
      // method: the rejections bisect toward the touch).
      if (max_free_penetration() <= gap_tolerance_m_) break;
      integrator_.retreat(0.5 * (integrator_.t_new() - integrator_.t_old()), stats_);
    }
    valid_begin_ = integrator_.t_old();
    valid_end_ = std::min(integrator_.t_new(), t_limit_s);
    ProfileScope scope(event_time_s_);
    // A lift-off or a friction transition is located even in a step cut
    // short by a drive change (after the restart it is no crossing); the
    // earlier ends the step. A breakaway just before a lift-off is located
    // first (the stick force rolling needs is read at F_n = 0: solve()); one
    // at the lift-off's own instant is the lift-off.
    if (system_.engaged) {
      const double t_liftoff = locate_liftoff();
      if (t_liftoff < valid_end_) valid_end_ = t_liftoff;
      const double t_transition = locate_friction_transition();
      if (t_transition < t_liftoff) {
        transition_at(t_transition);
        return;
      }
      if (t_liftoff == valid_end_) {
        // Redone only where the span is a step the integrator may take: a
        // lift-off within min_step_s of the step's start is interpolated over
        // that span, too short for the kink to matter.
        const bool redo = t_liftoff < integrator_.t_new() && t_liftoff - integrator_.t_old() >= min_step_s_;
        if (redo && !redo_step_to(t_liftoff) && pressing_at(valid_end_) > 0.0) {
          end_engaged_step(events);  // error control cut the redone step short, still pressed
          return;
        }
        lift_off_at(valid_end_, events);
        return;
      }
    }
    if (valid_end_ < integrator_.t_new()) return;  // a segment change restarts here
    if (system_.engaged) {
      end_engaged_step(events);
      return;
    }
    State x = integrator_.x_new();
    Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
    ModalState modal = modal_of<L>(x);
    const DriveState reference = system_.segment.at(valid_end_);
    DriveState d = model_.drive_at(k, reference);
    ContactGeometry g = model_.contact_geometry(k, d);
    if (g.penetration_m < -gap_tolerance_m_) return;  // free flight goes on
    if (opens(g, k)) return;                          // leaving: a rebound's first step (RigidBounce's cascade)
    // At the bore within tolerance: impact law, then engage if needed.
    ContactEvent e;
    e.t_s = valid_end_;
    bool settles = true, at_rest = false;
    if (closes(g, k)) {
      const FreeLoads free = loads(k, modal, d);
      const ImpactResult ir = apply_impact(model_, g, d, gap_tolerance_m_, free, k);
      // A motor's spin jumps with the impact, and the block with it (dxi' = h_xi dw).
      if constexpr (kMotor) {
        rotor_.add_spin_share(free.unbalance_dir, ir.spin_jump_rad_per_s, modal.tail(rotor_.modal_size()));
      }
      settles = ir.settles;
      at_rest = ir.sliding_stopped;
      e.normal_velocity_m_per_s = ir.closing_velocity_m_per_s;
      e.impulse_N_s = ir.normal_impulse_N_s;
    } else if (!(pressing_acceleration(model_, k, d, g, loads(k, modal, d)) > 0.0)) {
      return;  // at the bore, neither closing nor pressed: nothing happens
    }
    d = model_.drive_at(k, reference);  // a motor's spin took part in the impact
    g = model_.contact_geometry(k, d);
    const bool sustained = settles && pressing_acceleration(model_, k, d, g, loads(k, modal, d)) > 0.0;
    e.kind = sustained ? EventKind::kTouchdown : EventKind::kGraze;
    guard_.record(valid_end_);
    events.push_back(e);
    Pending next{true, valid_end_, k, modal, sustained, {}, true};
    if (sustained) {
      model_.project_onto_bore(g, k);
      next.kin = k;
      next.mode = mode_at(k, modal, d, at_rest || !model_.has_friction(), valid_end_);
    }
    defer(next);
  }

  double step_begin() const override { return valid_begin_; }
  double step_end() const override { return valid_end_; }

  Sample sample(double t_s) const override {
    const DenseState at = dense_state(t_s);
    const State& x = at.x;
    const Kinematics& k = at.k;
    const DriveState& d = at.d;
    const ContactGeometry& g = at.g;
    // A copy of the solver: sampling must not move the warm start of the
    // integration's own solves, or the trajectory would depend on the output
    // rate.
    const ContactForceSolver probe = solver_;
    long unused = 0;
    // At a friction transition's instant the sample reports the new regime
    // (a stick force that jumped out of the cone at a drive change is not
    // applied there, the slip force is).
    const FrictionMode& mode = pending_.due && pending_.engaged && t_s >= pending_.t_s ? pending_.mode : system_.mode;
    const FreeLoads free = loads(k, modal_of<L>(x), d);
    ContactForces f;
    if (system_.engaged) f = probe.solve(k, d, g, free, mode, false, t_s, unused);
    Sample s = make_sample(model_, t_s, k, d, g, f.normal_N, f.tangential_N, system_.engaged, &free);
    s.sticking = system_.engaged && mode.stick;
    rotor_.finish_sample(model_, modal_of<L>(x), free.unbalance_dir, s);
    return s;
  }

  const FlexibleRotorModel* flexible_rotor() const override { return rotor_.flexible(); }
  void change_rotor(double t_s, std::shared_ptr<const FlexibleRotorModel> rotor) override {
    integrator_.end_free_step_at(system_, t_s, stats_);  // under the old rotor
    rotor_.replace(std::move(rotor));
  }
  ModalState modal_state(double t_s) const override {
    if (rotor_.modal_size() == 0) return ModalState();  // no block: nothing to interpolate
    State x;
    integrator_.state_at(t_s, x);
    return modal_of<L>(x);
  }

  const RunStats& stats() const override { return stats_; }
  RunStats& mutable_stats() override { return stats_; }

 private:
  struct Pending {
    bool due = false;
    double t_s = 0.0;
    Kinematics kin;
    ModalState modal;  // a flexible rotor's [xi; xi'] with kin
    bool engaged = false;
    FrictionMode mode;
    bool new_mode = false;        // a friction regime begins here (touchdown, transition)
    bool from_breakaway = false;  // a slip that begins where rolling broke away
  };

  // The free loads of a state given by its station and block (the rotor's).
  FreeLoads loads(const Kinematics& k, const ModalState& modal, const DriveState& d) const {
    return loads_at(rotor_, model_, k, d, modal);
  }

  // The dense output's state at t and what the contact sees of it.
  struct DenseState {
    State x;
    Kinematics k;
    DriveState d;
    ContactGeometry g;
  };
  DenseState dense_state(double t_s) const {
    DenseState at;
    integrator_.state_at(t_s, at.x);
    at.k = kinematics_of<kStatorDof, kMotor, Rotor>(at.x);
    at.d = model_.drive_at(at.k, system_.segment.at(t_s));
    at.g = model_.contact_geometry(at.k, at.d);
    return at;
  }
  ContactGeometry geometry_at(double t_s) const { return dense_state(t_s).g; }

  // The largest penetration of the free step just taken, on its dense
  // output: at its midpoint and end and, where the gap's rate falls through
  // zero between two of them, at the located maximum (a graze inside the
  // step, which the end alone would let pass through the bore).
  double max_free_penetration() {
    const double t0 = integrator_.t_old(), t1 = integrator_.t_new();
    ContactGeometry prev = geometry_at(t0);
    double prev_t = t0, worst = -std::numeric_limits<double>::infinity();
    const int points = integrator_.free_scan_points();
    for (int i = 1; i <= points; ++i) {
      const double ti = scan_point(t0, t1, i, points);
      const ContactGeometry g = geometry_at(ti);
      worst = std::max(worst, g.penetration_m);
      if (prev.normal_velocity_m_per_s > 0.0 && g.normal_velocity_m_per_s < 0.0) {
        auto falling_rate = [this](double t) { return -geometry_at(t).normal_velocity_m_per_s; };
        const double tm =
            locate_event(falling_rate, prev_t, -prev.normal_velocity_m_per_s, ti, -g.normal_velocity_m_per_s, stats_);
        worst = std::max(worst, geometry_at(tm).penetration_m);
      }
      prev = g;
      prev_t = ti;
    }
    return worst;
  }

  // The friction regime at a state on the bore.
  FrictionMode mode_at(const Kinematics& k, const ModalState& modal, const DriveState& d, bool at_rest,
                       double t_s) const {
    const ContactGeometry g = model_.contact_geometry(k, d);
    const ContactForceSolver probe = solver_;
    long unused = 0;
    const ContactForces f = probe.solve(k, d, g, loads(k, modal, d), FrictionMode{}, true, t_s, unused);
    return select_friction_mode(g.sliding_velocity_m_per_s, at_rest, f.stick_N,
                                model_.parameters().friction_coefficient * f.normal_N);
  }

  // The friction event function of the engaged regime at t (an event when it
  // rises through 0): slip, -s v_slide; stick, |F_t,stick| - f F_n.
  double friction_event(double t_s) const {
    const DenseState at = dense_state(t_s);
    const State& x = at.x;
    const Kinematics& k = at.k;
    const DriveState& d = at.d;
    const ContactGeometry& g = at.g;
    if (!system_.mode.stick) return -system_.mode.slip_sign * g.sliding_velocity_m_per_s;
    const ContactForceSolver probe = solver_;
    long unused = 0;
    const ContactForces f = probe.solve(k, d, g, loads(k, modal_of<L>(x), d), system_.mode, true, t_s, unused);
    return std::abs(f.stick_N) - model_.parameters().friction_coefficient * f.normal_N;
  }

  // Locates a slip end or a breakaway inside the engaged step just taken, on
  // its dense output (the step's end alone would hide a sliding reversal).
  // Returns its time (the caller ends the step there and defers the restart
  // in the new friction regime: transition_at), or +infinity.
  double locate_friction_transition() {
    constexpr double kNone = std::numeric_limits<double>::infinity();
    if (!model_.has_friction()) return kNone;
    const double t0 = integrator_.t_old(), t1 = valid_end_;
    double prev_t = t0, prev_f = friction_event(t0);
    // At the step's start the function is either below zero (the regime
    // holds), on its surface because the regime began there, or above zero
    // at a step that is not a regime's start: it jumped there at a drive
    // change (the contact forces hold m e A and A R_r terms), and the
    // transition is now. On its surface the crossing right after the start
    // is found as the switching method's are (crossing(), event_scanner.hpp:
    // with a rate into the regime, slip from rest, the deflated bracket;
    // without, a slip begun at a breakaway, by probing nearer the start).
    EventWatch w;  // armed unless it starts at or above zero
    w.armed = true;
    w.regime_start_s = mode_start_s_;
    w.interior = system_.mode.stick;
    if (prev_f >= 0.0) {
      if (t0 != mode_start_s_) return t0;
      const double rate = friction_event_rate(t0);
      w.armed = false;
      w.on_surface = starts_on_surface(prev_f, rate);
      w.start_rate = rate;
      w.on_surface_without_rate = slip_from_breakaway_ && !w.on_surface;
    }
    auto f = [this](double t) { return friction_event(t); };
    // The step's scan points (scan_points()); a breakaway out of the cone
    // and back between two of them (the forcing turns the stick force:
    // config/sweeps/transitions.yaml) is found by the function's maximum
    // between them, its rate a difference quotient.
    for (int i = 1; i <= Dense::kEngagedScanPoints; ++i) {
      const double ti = scan_point(t0, t1, i, Dense::kEngagedScanPoints);
      const double fi = friction_event(ti);
      const double te = crossing(w, f, prev_t, prev_f, ti, fi, stats_);
      if (te < kNone) return te;
      w.armed = w.armed || fi < 0.0;
      prev_t = ti;
      prev_f = fi;
    }
    return kNone;
  }

  // The engaged regime's pressing at t (> 0: held): the pressing
  // acceleration of the dense output's state placed on the bore, what the
  // step's end is judged by (end_engaged_step).
  double pressing_at(double t_s) const {
    DenseState at = dense_state(t_s);
    model_.project_onto_bore(at.g, at.k);
    return pressing_acceleration(model_, at.k, at.d, model_.contact_geometry(at.k, at.d),
                                 loads(at.k, modal_of<L>(at.x), at.d));
  }

  // Locates a lift-off inside the engaged step just taken, on its dense
  // output: where the pressing falls through zero. Inside the step the
  // force is then zero and the rotor flies off the bore, so a long step
  // (dop853) would carry an engaged regime across a growing gap (2.6e-5 m,
  // 25 atol, at rtol 1e-3); located, the free flight starts there.
  // Returns the time, or +infinity when the step stays pressed.
  double locate_liftoff() {
    constexpr double kNone = std::numeric_limits<double>::infinity();
    const double t0 = integrator_.t_old(), t1 = valid_end_;
    double prev_t = t0, prev_p = pressing_at(t0);
    if (!(prev_p > 0.0)) return kNone;  // not pressed at the start: the step's end decides
    // A rotor's modes ring the pressing: a minimum that dips below zero and
    // back between two points is looked for too. The Jeffcott's pressing has
    // no such ringing.
    EventWatch w;
    w.armed = true;
    w.interior = !Rotor::kStationOnly;
    auto releasing = [this](double t) { return -pressing_at(t); };
    for (int i = 1; i <= Dense::kEngagedScanPoints; ++i) {
      const double ti = scan_point(t0, t1, i, Dense::kEngagedScanPoints);
      const double pressing_i = pressing_at(ti);
      const double te = crossing(w, releasing, prev_t, -prev_p, ti, -pressing_i, stats_);
      if (te < kNone) return te;
      prev_t = ti;
      prev_p = pressing_i;
    }
    return kNone;
  }

  // Redoes the engaged step just taken to end at t_s, a lift-off inside it:
  // past it the force is clamped at zero (a kink), so the interpolant there
  // is not the pressed motion (Golden.OtherLibmIsInEffectWhenPreloaded).
  // Returns false when error control cut the redone step short of t_s (it
  // ends where it got to); the first try counts as a rejected step.
  bool redo_step_to(double t_s) {
    const double dt_s = t_s - integrator_.t_old();
    integrator_.retreat(dt_s, stats_);
    integrator_.do_step(system_, stats_);
    valid_end_ = integrator_.t_new();
    return integrator_.t_new() == integrator_.t_old() + dt_s;
  }

  // Ends the step at a located lift-off (te on the side where the pressing
  // is <= 0): the free flight restarts there from the dense output's state
  // placed on the bore, as a held step's end is, since the interpolant's
  // drift of a few atol could start it beyond the gap tolerance
  // (PaperScene.IterationLocatesItsLiftOffs).
  void lift_off_at(double te, std::vector<ContactEvent>& events) {
    valid_end_ = te;
    State x;
    integrator_.state_at(te, x);
    Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
    model_.project_onto_bore(model_.contact_geometry(k, model_.drive_at(k, system_.segment.at(te))), k);
    guard_.record(te);
    events.push_back({te, EventKind::kLiftoff, 0.0, 0.0});
    defer({true, te, k, modal_of<L>(x), false, {}});
  }

  // Ends the step at te and defers the restart in the next friction regime.
  bool transition_at(double te) {
    valid_end_ = te;
    ++stats_.friction_transitions;
    guard_.record(te);
    State x;
    integrator_.state_at(te, x);
    Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(x);
    const ModalState modal = modal_of<L>(x);
    const DriveState d = model_.drive_at(k, system_.segment.at(te));
    const ContactGeometry g = model_.contact_geometry(k, d);
    model_.project_onto_bore(g, k);
    FrictionMode next;
    const bool breakaway = system_.mode.stick;
    if (breakaway) {
      // Rolling ends at v_slide = 0: the step's drift of it is projected
      // out, as at a held step's end, so the slip starts on its surface
      // (locate_friction_transition) and not up to the drift on its far side
      // (test_transitions.cpp, iteration on dop853 at rtol 1e-4).
      model_.hold_rolling(model_.contact_geometry(k, d), k);
      const ContactForceSolver probe = solver_;
      long unused = 0;
      const ContactForces f = probe.solve(k, d, g, loads(k, modal, d), system_.mode, true, te, unused);
      next.slip_sign = f.stick_N > 0.0 ? -1.0 : 1.0;
    } else {
      // Stick is judged where it starts, rolling (apply()): judged before, a
      // stick 19 % outside the cone began, which nothing ended (the dry whirl
      // at rtol 1e-3 before step()'s scan bound, which keeps it away there).
      Kinematics rolling = k;
      model_.hold_rolling(model_.contact_geometry(k, d), rolling);
      next = mode_at(rolling, modal, d, true, te);
    }
    defer({true, te, k, modal, true, next, true, breakaway});
    return true;
  }

  // d/dt of the slip event function at the start of the step (slip only;
  // a stick regime starts strictly inside the cone, never on its surface).
  double friction_event_rate(double t_s) const {
    if (system_.mode.stick) return 0.0;
    const Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(integrator_.x_old());
    const DriveState d = model_.drive_at(k, system_.segment.at(t_s));
    const ContactGeometry g = model_.contact_geometry(k, d);
    const ContactForceSolver probe = solver_;
    long unused = 0;
    const FreeLoads free = loads(k, modal_of<L>(integrator_.x_old()), d);
    const ContactForces f = probe.solve(k, d, g, free, system_.mode, false, t_s, unused);
    return -system_.mode.slip_sign * solver_.sliding_acceleration(k, d, g, free, f.normal_N, f.tangential_N);
  }

  void end_engaged_step(std::vector<ContactEvent>& events) {
    Kinematics k = kinematics_of<kStatorDof, kMotor, Rotor>(integrator_.x_new());
    const ModalState modal = modal_of<L>(integrator_.x_new());
    const DriveState d = model_.drive_at(k, system_.segment.at(valid_end_));
    const ContactGeometry g = model_.contact_geometry(k, d);
    Kinematics held = k;
    model_.project_onto_bore(g, held);
    const ContactGeometry gh = model_.contact_geometry(held, d);
    if (pressing_acceleration(model_, held, d, gh, loads(held, modal, d)) <= 0.0) {
      // Lift-off at the step's end, a step that was not pressed at its
      // start (locate_liftoff finds those that were): F_n = 0 already
      // separates, and the end is kept as integrated, its separation
      // velocity with it (the rotor has flown free for the whole step).
      guard_.record(valid_end_);
      events.push_back({valid_end_, EventKind::kLiftoff, 0.0, 0.0});
      defer({true, valid_end_, k, modal, false, {}});
      return;
    }
    // Still held: the drift of this step is projected out.
    stats_.max_constraint_violation_m = std::max(stats_.max_constraint_violation_m, std::abs(g.penetration_m));
    stats_.min_abs_sliding_velocity_m_per_s =
        std::min(stats_.min_abs_sliding_velocity_m_per_s, std::abs(gh.sliding_velocity_m_per_s));
    if (system_.mode.stick) model_.hold_rolling(model_.contact_geometry(held, d), held);
    defer({true, valid_end_, held, modal, true, system_.mode});
  }

  void defer(const Pending& p) { pending_ = p; }

  void apply(Pending p) {
    system_.engaged = p.engaged;
    system_.mode = p.mode;
    if (p.new_mode) {
      mode_start_s_ = p.t_s;
      slip_from_breakaway_ = p.from_breakaway;
    }
    if (p.engaged && p.mode.stick) {
      model_.hold_rolling(model_.contact_geometry(p.kin, model_.drive_at(p.kin, system_.segment.at(p.t_s))), p.kin);
    }
    restart_from(p.t_s, p.kin, p.modal, integrator_.dt());
  }

  void restart_from(double t_s, const Kinematics& k, const ModalState& modal, double dt) {
    State x = sized_state<L>(modal);
    store_kinematics<kStatorDof, kMotor, Rotor>(k, x);
    integrator_.initialize(system_, x, t_s, dt, stats_);
    valid_begin_ = valid_end_ = t_s;
  }

  double mode_start_s_ = -1.0;        // when the current friction regime began
  bool slip_from_breakaway_ = false;  // that regime is a slip begun at a breakaway
  Rotor rotor_;
  StationModel model_;  // the station (Rotor::adopt)
  ContactForceSolver solver_;
  IterationSystem<kStatorDof, kMotor, Rotor> system_;
  Dense integrator_;
  double min_step_s_;
  double initial_step_s_;
  double gap_tolerance_m_;
  ChatterGuard guard_;
  double valid_begin_ = 0.0, valid_end_ = 0.0;
  Pending pending_;  // a restart (projection, impact, regime) due at pending_.t_s
  RunStats stats_;
  double* event_time_s_ = nullptr;    // profiling only
  double* restart_time_s_ = nullptr;  // profiling only
};

template <Integrator kScheme, class Rotor>
struct IterationOn {
  template <int kStatorDof, bool kMotor>
  using Method = IterationMethod<kStatorDof, kMotor, Rotor, kScheme>;
};

// The method for a scene on one kind of rotor: the Jeffcott's (fixed-size
// states) or a flexible rotor's, each kind in its own translation unit
// (the classes keep the internal linkage the compiler inlines best).
template <Integrator I, class Rotor>
std::unique_ptr<ContactMethod> make_iteration_for_rotor(const Scene& scene) {
  return make_for_scene<IterationOn<I, Rotor>::template Method>(scene);
}

}  // namespace
}  // namespace rotor_rub::core
