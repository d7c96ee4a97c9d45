// The penalty method's class template and its factory, included by one
// translation unit per kind of rotor (penalty_method_jeffcott.cpp and
// penalty_method_flexible.cpp): both in one unit made the build's longest
// compile (docs/testing.md). Private to those two: its unnamed namespace
// gives each its own copy, and they share nothing of it (the registry calls
// each unit's factory, make_penalty_jeffcott and make_penalty_flexible).
#pragma once

#include <array>
#include <limits>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "contact/penalty_law.hpp"
#include "integrators/dense_dopri5.hpp"
#include "integrators/dense_rk4.hpp"
#include "integrators/dense_rodasp.hpp"
#include "methods/event_scanner.hpp"
#include "methods/method_factory.hpp"
#include "methods/penalty_method.hpp"
#include "methods/penalty_system.hpp"
#include "rotor/rotor_model.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "run/cost_profiler.hpp"
#include "run/sample_builder.hpp"

namespace rotor_rub::core {
namespace {

template <class Integrator>
Integrator make_integrator(const SolverSettings& s) {
  if constexpr (is_fixed_step<Integrator>::value) {
    return Integrator(s.fixed_step_s, s.max_steps);
  } else {
    return Integrator(s.atol, s.rtol, s.min_step_s, s.max_steps);
  }
}

// Rotor: the rotor model (rotor_model.hpp), its block carried through every
// restart.
template <int kStatorDof, bool kMotor, class Integrator, class Rotor>
class PenaltyMethod final : public ContactMethod {
 public:
  using L = FreeLayout<kStatorDof, kMotor, Rotor>;
  using State = typename L::State;
  static constexpr bool kModeLocked = is_implicit<Integrator>::value;
  // The implicit integrator's pressed mode in the contact's polar
  // coordinates (a rotor's block beside them, as in the Cartesian state).
  static constexpr bool kPolar = kModeLocked;
  using Polar = PenaltyPolarSystem<kStatorDof, kMotor, kModeLocked, Rotor>;

  explicit PenaltyMethod(const Scene& scene)
      : rotor_(scene),
        model_(rotor_.adopt(scene.model)),
        integrator_(make_integrator<Integrator>(scene.solver)),
        initial_step_s_(scene.solver.initial_step_s) {
    system_.model = &model_;
    system_.rotor = &rotor_;
    system_.law = PenaltyLaw(model_);
    if constexpr (kPolar) polar_sys_.cartesian = &system_;
    if (scene.solver.profile_cost) {
      system_.rhs_time_s = &stats_.rhs_time_s;
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
    crossed_edge_ = -1;
    fallback_ = false;
    if constexpr (kPolar && !kMotor) polar_sys_.reserve(L::kSize + modal.size());  // its closed-form Jacobian's
    restart(t_s, k, modal, initial_step_s_);
  }

  void change_segment(double t_s, const SpeedSegment& segment) override {
    end_step_at(t_s);
    const Kinematics k = kinematics_at(t_s);
    system_.segment = segment;
    // A mode change due exactly here carries over; one later in the step is
    // found again after the restart.
    if (!(pending_ && valid_end_ == t_s)) crossed_edge_ = -1;
    restart(t_s, k, modal_at(t_s), integrator_.dt());
    ++stats_.restarts;
  }

  void change_model(double t_s, const ModelParameters& p, std::vector<ContactEvent>& events) override {
    ProfileScope scope(restart_time_s_);
    end_step_at(t_s);
    Kinematics k = kinematics_at(t_s);
    const bool was_pressed = system_.law.edges(geometry_at(t_s))[kPressedEdge] > 0.0;
    const Vec2 old_frame = model_.frame_shift();
    model_ = StationModel(rotor_.adopt(p));
    system_.law = PenaltyLaw(model_);
    k.rotor_pos += old_frame - model_.frame_shift();
    crossed_edge_ = -1;
    fallback_ = false;
    restart(t_s, k, modal_at(t_s), integrator_.dt());
    ++stats_.restarts;
    // The law's force jumps with the parameters: only a clearance or a bore
    // moved away can end a contact here (one that would press deeper is
    // refused before).
    if (was_pressed && !(edges_end_[kPressedEdge] > 0.0)) events.push_back({t_s, EventKind::kLiftoff, 0.0, 0.0});
  }

  void step(double t_limit_s, std::vector<ContactEvent>& events) override {
    if (pending_) {
      // The mode changed at the end of the last step: restart there, in the
      // new mode, keeping the step size the controller had reached (a
      // fallback keeps the step that found its edge instead).
      ProfileScope scope(restart_time_s_);
      end_step_at(valid_end_);
      restart(valid_end_, kinematics_at(valid_end_), modal_at(valid_end_),
              fallback_ ? fallback_dt_s_ : integrator_.dt());
      ++stats_.restarts;
    }
    with_system([this](auto& sys) { integrator_.do_step(sys, stats_); });
    ProfileScope scope(event_time_s_);
    const double t0 = integrator_.t_old();
    const double t1 = std::min(integrator_.t_new(), t_limit_s);
    double prev_t = t0;
    PenaltyEdgeValues prev = edges_end_;
    ContactGeometry g_end;
    // Out of contact the field has no contact force: a contact that begins
    // and ends between two scan points would go unfelt. The gap's closest
    // approach (delta' from closing to opening) is checked for it.
    const bool free_field = !system_.mode.clamped && edges_end_steps(system_.mode) && !system_.mode.pressed;
    double prev_vn = free_field ? geometry_at(t0).normal_velocity_m_per_s : 0.0;
    for (int i = 1; i <= kScanPoints; ++i) {
      const double ti = scan_point(t0, t1, i, kScanPoints);
      g_end = geometry_at(ti);
      PenaltyEdgeValues cur = system_.law.edges(g_end);
      double t_cur = ti;
      if (free_field && !(cur[kPressedEdge] > 0.0) && prev_vn > 0.0 && g_end.normal_velocity_m_per_s < 0.0) {
        auto vn = [this](double t) { return geometry_at(t).normal_velocity_m_per_s; };
        const double closest = locate_event(vn, prev_t, prev_vn, ti, g_end.normal_velocity_m_per_s, stats_);
        const PenaltyEdgeValues at_closest = edges_at(closest);
        if (at_closest[kPressedEdge] > 0.0) {  // the touchdown lies before it
          cur = at_closest;
          t_cur = closest;
        }
      }
      if (system_.mode.clamped || !edges_end_steps(system_.mode)) {
        report_contact_change(prev_t, prev, ti, cur, events);
      } else if (system_.law.mode_of(cur) != system_.mode) {
        const auto [te, edge] = earliest_crossing(prev_t, prev, t_cur, cur);
        on_edge(te, edge, events);
        return;
      }
      prev_t = ti;
      prev = cur;
      prev_vn = g_end.normal_velocity_m_per_s;
    }
    valid_end_ = t1;
    edges_end_ = prev;
    edges_in_row_ = 0;
    // A fallback step (on_edge()) on the clamped law ends here: the next
    // restarts in the mode of the state it reached.
    if (system_.mode.clamped) pending_ = true;
    // An explicit integrator's contact ends without a restart: out of
    // contact the clamped law's force is zero, the free mode's field.
    if (!kModeLocked && system_.mode.pressed && !(edges_end_[kPressedEdge] > 0.0)) system_.mode = PenaltyMode{};
    if (system_.law.mode_of(edges_end_).pressed) {  // g_end is at valid_end_ = t1
      stats_.min_abs_sliding_velocity_m_per_s =
          std::min(stats_.min_abs_sliding_velocity_m_per_s, std::abs(g_end.sliding_velocity_m_per_s));
    }
  }

  double step_begin() const override { return integrator_.t_old(); }
  double step_end() const override { return valid_end_; }

  Sample sample(double t_s) const override {
    const Kinematics k = kinematics_at(t_s);
    const DriveState d = model_.drive_at(k, system_.segment.at(t_s));
    const ContactGeometry g = model_.contact_geometry(k, d);
    // The clamped law: inside a step it equals the mode's (the step ends at
    // the mode's edge), and it never reports a pulling force.
    const double fn = system_.law.normal(g);
    const double ft = system_.law.tangential(g, fn);
    const ModalState modal = modal_at(t_s);
    Sample s;
    Vec2 unbalance_dir;
    if constexpr (kMotor) {
      // The spin's acceleration with the rotor's coupling (a block's included).
      const FreeLoads free = loads_at(rotor_, model_, k, d, modal);
      s = make_sample(model_, t_s, k, d, g, fn, ft, fn > 0.0, &free);
      unbalance_dir = free.unbalance_dir;
    } else {
      s = make_sample(model_, t_s, k, d, g, fn, ft, fn > 0.0);
      unbalance_dir = model_.unbalance_dir(d.angle_rad);
    }
    s.sticking = s.in_contact && std::abs(ft) < system_.law.friction_coefficient * fn;
    rotor_.finish_sample(model_, modal, unbalance_dir, s);
    return s;
  }

  const FlexibleRotorModel* flexible_rotor() const override { return rotor_.flexible(); }
  void change_rotor(double t_s, std::shared_ptr<const FlexibleRotorModel> rotor) override {
    end_step_at(t_s);  // under the old rotor (Faults.BladeLossActsFromItsInstant)
    rotor_.replace(std::move(rotor));
  }
  ModalState modal_state(double t_s) const override { return modal_at(t_s); }

  const RunStats& stats() const override { return stats_; }
  RunStats& mutable_stats() override { return stats_; }

 private:
  // Points at which the edges are checked (scan_points: two on dopri5,
  // rosenbrock4 and rk4, the last the step's end): a contact shorter than a
  // step (a graze in free flight, where the integrator sees no force) is
  // found if it spans one of them. An edge crossed and crossed back between
  // two of them goes unseen (as in the switching method's scan): for that
  // while the mode's extended law acts (a pressed mode's force slightly
  // pulling, or none in free flight) where the samples report the clamped law.
  static constexpr int kScanPoints = scan_points(Integrator::kScheme);
  static constexpr double kNoProgress = 1e-9;  // of the step: an edge at its start
  static constexpr int kMaxEdgesInRow = 64;

  // Whether the mode's edges end a step (the field is the mode's, smooth):
  // every edge for the implicit integrator; for the explicit ones only the
  // touchdown, out of contact (penalty_system.hpp).
  static bool edges_end_steps(const PenaltyMode& mode) { return kModeLocked || !mode.pressed; }

  // The implicit integrator restarts from a step's end (DenseRodasp::end_step_at).
  void end_step_at(double t_s) {
    if constexpr (kModeLocked) with_system([this, t_s](auto& sys) { integrator_.end_step_at(sys, t_s, stats_); });
  }

  // f(the system of the piece being integrated): the pressed mode's in
  // polar coordinates (penalty_system.hpp), else the Cartesian one.
  template <class F>
  void with_system(F&& f) {
    if constexpr (kPolar) {
      if (polar_) {
        f(polar_sys_);
        return;
      }
    }
    f(system_);
  }

  Kinematics kinematics_at(double t_s) const {
    State x;
    integrator_.state_at(t_s, x);
    if constexpr (kPolar) {
      if (polar_) return Polar::kinematics(x);
    }
    return kinematics_of<kStatorDof, kMotor, Rotor>(x);
  }
  // The rotor's block at t_s (a flexible rotor's [xi; xi']; none: empty).
  ModalState modal_at(double t_s) const {
    if (rotor_.modal_size() == 0) return ModalState();  // nothing to interpolate
    State x;
    integrator_.state_at(t_s, x);
    return modal_of<L>(x);
  }

  // Restarts at t_s from state k. After an edge (crossed_edge_ >= 0) the
  // mode is the one the crossing located on the dense output leads to: the
  // step to t_s taken again (end_step_at) may end a rounding short of the
  // edge, where deciding the mode from the state would find the same edge
  // again at once. The edge's value is taken as on its new side, so only a
  // crossing back is seen.
  void restart(double t_s, const Kinematics& k, const ModalState& modal, double dt_s) {
    pending_ = false;
    const DriveState d = model_.drive_at(k, system_.segment.at(t_s));
    edges_end_ = system_.law.edges(model_.contact_geometry(k, d));
    if (crossed_edge_ >= 0 && (edges_end_[crossed_edge_] > 0.0) != crossed_to_positive_) {
      edges_end_[crossed_edge_] = crossed_to_positive_ ? std::numeric_limits<double>::denorm_min() : 0.0;
    }
    crossed_edge_ = -1;
    system_.mode = system_.law.mode_of(edges_end_);
    system_.mode.clamped = fallback_;
    fallback_ = false;
    // A pressed contact has delta > 0 (> C but for a rounding at a crossed
    // edge): its polar coordinates exist. A fallback step stays Cartesian.
    polar_ = kPolar && system_.mode.pressed && !system_.mode.clamped;
    State x = sized_state<L>(modal);
    if constexpr (kPolar) {
      if (polar_) Polar::store(k, x);
    }
    if (!polar_) store_kinematics<kStatorDof, kMotor, Rotor>(k, x);
    with_system([&](auto& sys) { integrator_.initialize(sys, x, t_s, dt_s, stats_); });
    valid_end_ = t_s;
  }

  // The earliest sign change in (t0, t1] of an edge that bounds the mode, and the edge.
  std::pair<double, int> earliest_crossing(double t0, const PenaltyEdgeValues& e0, double t1,
                                           const PenaltyEdgeValues& e1) {
    double first = t1;
    int edge = -1;
    for (int k = 0; k < kPenaltyEdges; ++k) {
      if (!system_.law.watched(k, system_.mode) || (e0[k] > 0.0) == (e1[k] > 0.0)) continue;
      auto f = [this, k](double t) { return signed_edge(edges_at(t)[k]); };
      const double te = locate_event(f, t0, signed_edge(e0[k]), t1, signed_edge(e1[k]), stats_);
      if (edge < 0 || te < first) {
        first = te;
        edge = k;
      }
    }
    return {first, edge < 0 ? kPressedEdge : edge};
  }

  // Explicit integrators in contact (and a fallback step), whose field is the
  // clamped law: touchdown and lift-off located for the report only.
  void report_contact_change(double t0, const PenaltyEdgeValues& e0, double t1, const PenaltyEdgeValues& e1,
                             std::vector<ContactEvent>& events) {
    if ((e0[kPressedEdge] > 0.0) == (e1[kPressedEdge] > 0.0)) return;
    auto f = [this](double t) { return signed_edge(edges_at(t)[kPressedEdge]); };
    ContactEvent e;
    e.t_s = locate_event(f, t0, signed_edge(e0[kPressedEdge]), t1, signed_edge(e1[kPressedEdge]), stats_);
    e.kind = e1[kPressedEdge] > 0.0 ? EventKind::kTouchdown : EventKind::kLiftoff;
    if (e.kind == EventKind::kTouchdown) e.normal_velocity_m_per_s = geometry_at(e.t_s).normal_velocity_m_per_s;
    events.push_back(e);
  }

  // An edge value with 0 counted as negative (not positive), as mode_of()
  // counts it, so that the root finder sees a strict sign change.
  static double signed_edge(double v) { return v > 0.0 ? v : std::min(v, -std::numeric_limits<double>::denorm_min()); }

  // The step ends at the edge; the next step() restarts in the new mode.
  // An edge found at the very start of a step that began at an edge (no
  // progress: the new mode's field turns straight back across it) is a
  // graze: the edge touched with zero slope, or a contact force below what
  // the tolerance resolves (at a loose rtol the position error allowed can
  // be hundreds of times the penetration). The modes would hand the state
  // back and forth at one instant, so such a step is taken again on the
  // clamped law itself, which is always the law, only not smooth; the next
  // step restarts in the mode of the state it reaches (ContactEvents.
  // EveryGrazeCloses).
  void on_edge(double t_s, int edge, std::vector<ContactEvent>& events) {
    const double t0 = integrator_.t_old();
    const double h = integrator_.t_new() - t0;
    // "At its start": within the root's resolution (kEventTimeTolerance_s),
    // a few ulps of t, or a billionth of the step; or the steps have ended
    // at edges kMaxEdgesInRow times running (no real sequence of the three
    // edges is that long), whatever the progress.
    const double at_start =
        std::max({kNoProgress * h, 4.0 * kEventTimeTolerance_s, 4.0 * (std::nextafter(t0, 2.0 * t0 + 1.0) - t0)});
    if (t_s - t0 <= at_start || ++edges_in_row_ > kMaxEdgesInRow) {
      edges_in_row_ = 0;
      fallback_ = true;
      fallback_dt_s_ = h;  // the step that found the edge, not the controller's next proposal
      valid_end_ = t0;
      edges_end_ = edges_at(t0);
      pending_ = true;
      return;
    }
    valid_end_ = t_s;
    edges_end_ = edges_at(t_s);
    crossed_edge_ = edge;
    crossed_to_positive_ = edges_end_[edge] > 0.0;
    const PenaltyMode next = system_.law.mode_of(edges_end_);
    if (system_.mode.pressed) {  // a stick-slip edge is where the sliding speed is smallest
      stats_.min_abs_sliding_velocity_m_per_s =
          std::min(stats_.min_abs_sliding_velocity_m_per_s, std::abs(geometry_at(t_s).sliding_velocity_m_per_s));
    }
    // (If the root's far side rounded back into the mode, the restart
    // continues in it: the step has ended at t_s all the same.)
    if (next.pressed != system_.mode.pressed) {
      ContactEvent e;
      e.t_s = t_s;
      e.kind = next.pressed ? EventKind::kTouchdown : EventKind::kLiftoff;
      if (next.pressed) e.normal_velocity_m_per_s = geometry_at(t_s).normal_velocity_m_per_s;
      events.push_back(e);
    }
    pending_ = true;
  }

  ContactGeometry geometry_at(double t_s) const {
    const Kinematics k = kinematics_at(t_s);
    return model_.contact_geometry(k, model_.drive_at(k, system_.segment.at(t_s)));
  }
  PenaltyEdgeValues edges_at(double t_s) const { return system_.law.edges(geometry_at(t_s)); }

  Rotor rotor_;
  StationModel model_;  // the station (Rotor::adopt)
  PenaltySystem<kStatorDof, kMotor, kModeLocked, Rotor> system_;
  struct NoPolar {};
  std::conditional_t<kPolar, Polar, NoPolar> polar_sys_;
  bool polar_ = false;  // the integrator's state is polar_sys_'s (kPolar, the pressed mode)
  Integrator integrator_;
  double initial_step_s_;
  PenaltyEdgeValues edges_end_{};  // at valid_end_
  double valid_end_ = 0.0;
  bool pending_ = false;
  int crossed_edge_ = -1;  // the edge the pending restart crossed, and to which side
  bool crossed_to_positive_ = false;
  bool fallback_ = false;  // the next restart takes one step on the clamped law
  double fallback_dt_s_ = 0.0;
  int edges_in_row_ = 0;  // steps ended at an edge since the last full step
  RunStats stats_;
  double* event_time_s_ = nullptr;    // profiling only
  double* restart_time_s_ = nullptr;  // profiling only
};

// The dense stepper of each integrator the penalty method runs on.
template <Integrator kScheme, class State>
using PenaltyStepper =
    std::conditional_t<kScheme == Integrator::kRosenbrock4, DenseRodasp<State>,
                       std::conditional_t<kScheme == Integrator::kRk4, DenseRk4<State>, DenseDopri5<State>>>;

template <Integrator kScheme, class Rotor>
struct PenaltyOn {
  template <int kStatorDof, bool kMotor>
  using Method = PenaltyMethod<kStatorDof, kMotor,
                               PenaltyStepper<kScheme, typename FreeLayout<kStatorDof, kMotor, Rotor>::State>, Rotor>;
};

// The method for a scene on one kind of rotor: the Jeffcott's (fixed-size
// states) or a flexible rotor's, each kind in its own translation unit
// (the classes keep the internal linkage the compiler inlines best).
template <Integrator I, class Rotor>
std::unique_ptr<ContactMethod> make_penalty_for_rotor(const Scene& scene) {
  return make_for_scene<PenaltyOn<I, Rotor>::template Method>(scene);
}

}  // namespace
}  // namespace rotor_rub::core
