#include "rotor_rub_sim/core/switching_method.hpp"

#include <cmath>

#include "rotor_rub_sim/core/chatter_guard.hpp"
#include "rotor_rub_sim/core/constrained_dynamics.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/cost_profiler.hpp"
#include "rotor_rub_sim/core/dense_dopri5.hpp"
#include "rotor_rub_sim/core/event_location.hpp"
#include "rotor_rub_sim/core/sample_builder.hpp"

namespace rotor_rub::core {
namespace {

template <int kStatorDof>
struct FreeFlightSystem {
  using L = FreeLayout<kStatorDof>;
  const JeffcottModel* model;
  SpeedSegment segment;
  double* rhs_time_s = nullptr;  // profiling only
  void operator()(const typename L::State& x, typename L::State& dxdt, double t) const {
    ProfileScope scope(rhs_time_s);
    const Kinematics k = kinematics_of<kStatorDof>(x);
    const DriveState d = segment.at(t);
    dxdt.template segment<2>(L::kRotorPos) = k.rotor_vel;
    dxdt.template segment<2>(L::kRotorVel) = model->rotor_free_force(k, d) * model->inv_rotor_mass();
    if constexpr (kStatorDof == 2) {
      dxdt.template segment<2>(L::kStatorPos) = k.stator_vel;
      dxdt.template segment<2>(L::kStatorVel) = model->stator_free_force(k) * model->inv_stator_mass();
    }
  }
};

template <int kStatorDof>
struct ContactSystem {
  using L = ContactLayout<kStatorDof>;
  ConstrainedDynamics<kStatorDof> dynamics;
  SpeedSegment segment;
  double* rhs_time_s = nullptr;  // profiling only
  void operator()(const typename L::State& x, typename L::State& dxdt, double t) const {
    ProfileScope scope(rhs_time_s);
    dynamics.derivative(x, segment.at(t), dxdt);
  }
};

enum class Regime { kFree, kContact };

template <int kStatorDof>
class SwitchingMethod final : public ContactMethod {
 public:
  using FL = FreeLayout<kStatorDof>;
  using CL = ContactLayout<kStatorDof>;

  explicit SwitchingMethod(const Scene& scene)
      : model_(scene.model),
        free_int_(scene.solver.atol, scene.solver.rtol, scene.solver.min_step_s, scene.solver.max_steps),
        contact_int_(scene.solver.atol, scene.solver.rtol, scene.solver.min_step_s, scene.solver.max_steps),
        initial_step_s_(scene.solver.initial_step_s),
        penetration_tolerance_m_(scene.solver.atol),
        guard_(scene.solver.max_events_per_ms) {
    free_sys_.model = &model_;
    contact_sys_.dynamics.model = &model_;
    if (scene.solver.profile_cost) free_sys_.rhs_time_s = contact_sys_.rhs_time_s = &stats_.rhs_time_s;
  }

  void start(double t_s, const Kinematics& k, const SpeedSegment& segment) override {
    free_sys_.segment = contact_sys_.segment = segment;
    regime_ = Regime::kFree;
    pending_ = false;
    enter_free(t_s, k, initial_step_s_);
  }

  void change_segment(double t_s, const SpeedSegment& segment) override {
    free_sys_.segment = contact_sys_.segment = segment;
    ++stats_.restarts;
    if (pending_) {
      // An event exactly here carries over (the state at an instant does not
      // depend on the drive ahead); one later in the step was found under the
      // old drive and is dropped (the caller drops its report).
      if (pending_t_ <= t_s) return;
      pending_ = false;
    }
    if (regime_ == Regime::kFree) {
      typename FL::State x;
      free_int_.state_at(t_s, x);
      const double dt = free_int_.dt();
      free_int_.initialize(free_sys_, x, t_s, dt, stats_);
      event_value_end_ = free_event_value(t_s);
    } else {
      typename CL::State x;
      contact_int_.state_at(t_s, x);
      const double dt = contact_int_.dt();
      contact_int_.initialize(contact_sys_, x, t_s, dt, stats_);
      event_value_end_ = contact_event_value(t_s);
    }
    valid_begin_ = valid_end_ = t_s;
  }

  void step(double t_limit_s, std::vector<ContactEvent>& events) override {
    if (pending_) apply_pending();
    if (regime_ == Regime::kFree) {
      free_int_.do_step(free_sys_, stats_);
      scan(free_int_.t_old(), std::min(free_int_.t_new(), t_limit_s), events);
    } else {
      contact_int_.do_step(contact_sys_, stats_);
      scan(contact_int_.t_old(), std::min(contact_int_.t_new(), t_limit_s), events);
      record_contact_quality(valid_end_);
    }
  }

  double step_begin() const override { return valid_begin_; }
  double step_end() const override { return valid_end_; }

  Sample sample(double t_s) const override {
    const DriveState d = free_sys_.segment.at(t_s);
    if (regime_ == Regime::kFree) {
      typename FL::State x;
      free_int_.state_at(t_s, x);
      return make_sample(model_, t_s, kinematics_of<kStatorDof>(x), d, 0.0, false);
    }
    typename CL::State x;
    contact_int_.state_at(t_s, x);
    const auto c = contact_sys_.dynamics.evaluate(x, d);
    return make_sample(model_, t_s, c.kin, d, c.normal_force_N, true);
  }

  const RunStats& stats() const override { return stats_; }
  RunStats& mutable_stats() override { return stats_; }

 private:
  // Event function of the current regime: free: delta - C (event when it
  // rises through 0); contact: -F_n (event when F_n falls through 0).
  double free_event_value(double t_s) const {
    typename FL::State x;
    free_int_.state_at(t_s, x);
    return model_.contact_geometry(kinematics_of<kStatorDof>(x), free_sys_.segment.at(t_s)).penetration_m;
  }
  double contact_event_value(double t_s) const {
    typename CL::State x;
    contact_int_.state_at(t_s, x);
    return -contact_sys_.dynamics.evaluate(x, contact_sys_.segment.at(t_s)).normal_force_N;
  }
  double event_value(double t_s) const {
    return regime_ == Regime::kFree ? free_event_value(t_s) : contact_event_value(t_s);
  }

  // Checks the event function at the step's quarter points (so a graze inside
  // one step is not missed) and locates the first upward zero crossing.
  void scan(double t0, double t1, std::vector<ContactEvent>& events) {
    valid_begin_ = t0;
    double prev_t = t0, prev_v = event_value_end_;
    for (int i = 1; i <= kScanPoints; ++i) {
      const double ti = i == kScanPoints ? t1 : t0 + (t1 - t0) * i / kScanPoints;
      const double vi = event_value(ti);
      if (armed_ && prev_v < 0.0 && vi >= 0.0) {
        auto f = [this](double t) { return event_value(t); };
        const double te = locate_event(f, prev_t, prev_v, ti, vi, stats_);
        valid_end_ = te;
        event_value_end_ = 0.0;
        on_event(te, events);
        return;
      }
      if (vi < 0.0) armed_ = true;
      prev_t = ti;
      prev_v = vi;
    }
    valid_end_ = t1;
    event_value_end_ = prev_v;
    // Free flight that never opened the gap after a switch, yet penetrates:
    // force contact (the paper's remedy for the stall).
    if (!armed_ && regime_ == Regime::kFree && prev_v > penetration_tolerance_m_) on_event(t1, events);
  }

  void on_event(double te, std::vector<ContactEvent>& events) {
    guard_.record(te);
    const DriveState d = free_sys_.segment.at(te);
    ContactEvent e;
    e.t_s = te;
    if (regime_ == Regime::kContact) {
      e.kind = EventKind::kLiftoff;
      next_kin_ = sample(te).kin;
      next_regime_ = Regime::kFree;
    } else {
      Kinematics k = sample(te).kin;
      const ContactGeometry g = model_.contact_geometry(k, d);
      bool settles = true;
      if (g.normal_velocity_m_per_s > 0.0) {
        const ImpactResult ir = apply_impact(model_, g, k);
        settles = ir.settles;
        e.normal_velocity_m_per_s = ir.closing_velocity_m_per_s;
        e.impulse_N_s = ir.normal_impulse_N_s;
      }
      next_kin_ = k;
      const bool sustained =
          settles && contact_sys_.dynamics.evaluate(contact_sys_.dynamics.reduce(k), d).normal_force_N > 0.0;
      next_regime_ = sustained ? Regime::kContact : Regime::kFree;
      e.kind = sustained ? EventKind::kTouchdown : EventKind::kGraze;
    }
    events.push_back(e);
    pending_t_ = te;
    pending_ = true;
  }

  void apply_pending() {
    pending_ = false;
    ++stats_.restarts;
    const double dt = regime_ == Regime::kFree ? free_int_.dt() : contact_int_.dt();
    if (next_regime_ == Regime::kFree) {
      regime_ = Regime::kFree;
      enter_free(pending_t_, next_kin_, dt);
    } else {
      regime_ = Regime::kContact;
      const typename CL::State x = contact_sys_.dynamics.reduce(next_kin_);
      contact_int_.initialize(contact_sys_, x, pending_t_, dt, stats_);
      armed_ = true;  // touchdown required F_n > 0
      event_value_end_ = contact_event_value(pending_t_);
      valid_begin_ = valid_end_ = pending_t_;
    }
  }

  void enter_free(double t_s, const Kinematics& k, double dt) {
    typename FL::State x;
    store_kinematics<kStatorDof>(k, x);
    free_int_.initialize(free_sys_, x, t_s, dt, stats_);
    event_value_end_ = free_event_value(t_s);
    armed_ = event_value_end_ < 0.0;
    valid_begin_ = valid_end_ = t_s;
  }

  void record_contact_quality(double t_s) {
    // The constraint holds by construction; record the sliding speed to show
    // where the run stands against the friction regularisation band.
    const Sample s = sample(t_s);
    stats_.min_abs_sliding_velocity_m_per_s =
        std::min(stats_.min_abs_sliding_velocity_m_per_s, std::abs(s.sliding_velocity_m_per_s));
    stats_.max_constraint_violation_m = std::max(stats_.max_constraint_violation_m, std::abs(s.penetration_m));
  }

  static constexpr int kScanPoints = 4;
  JeffcottModel model_;
  FreeFlightSystem<kStatorDof> free_sys_;
  ContactSystem<kStatorDof> contact_sys_;
  DenseDopri5<typename FL::State> free_int_;
  DenseDopri5<typename CL::State> contact_int_;
  double initial_step_s_;
  double penetration_tolerance_m_;
  ChatterGuard guard_;
  Regime regime_ = Regime::kFree;
  bool armed_ = false;
  double event_value_end_ = -1.0;
  double valid_begin_ = 0.0, valid_end_ = 0.0;
  bool pending_ = false;
  double pending_t_ = 0.0;
  Regime next_regime_ = Regime::kFree;
  Kinematics next_kin_;
  RunStats stats_;
};

}  // namespace

std::unique_ptr<ContactMethod> make_switching_method(const Scene& scene) {
  if (scene.model.stator_model == StatorModel::kRigid) return std::make_unique<SwitchingMethod<0>>(scene);
  return std::make_unique<SwitchingMethod<2>>(scene);
}

}  // namespace rotor_rub::core
