#include "rotor_rub_sim/core/iteration_method.hpp"

#include <boost/math/tools/roots.hpp>
#include <cmath>

#include "rotor_rub_sim/core/chatter_guard.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/cost_profiler.hpp"
#include "rotor_rub_sim/core/dense_dopri5.hpp"
#include "rotor_rub_sim/core/sample_builder.hpp"

namespace rotor_rub::core {
namespace {

// Finds the normal force that holds delta'' = 0, or 0 when none is needed.
class NormalForceSolver {
 public:
  NormalForceSolver(const JeffcottModel* m, double rtol, int max_iterations)
      : model_(m), rtol_(rtol), max_iterations_(max_iterations) {}

  // delta'' under normal force F [m/s^2].
  double distance_acceleration(const Kinematics& k, const DriveState& d, const ContactGeometry& g, double f) const {
    Vec2 ar, as;
    model_->accelerations(k, d, g, f, ar, as);
    return JeffcottModel::distance_acceleration(k, g, ar, as);
  }

  double solve(const Kinematics& k, const DriveState& d, const ContactGeometry& g, double t_s, long& iterations) const {
    const double r0 = distance_acceleration(k, d, g, 0.0);
    ++iterations;
    if (!(r0 > 0.0)) return 0.0;  // separating without help: released
    // Bracket: grow from the last root until delta'' turns negative.
    double hi = std::max(last_force_N_ * 2.0, 1e-3);
    double r_hi = distance_acceleration(k, d, g, hi);
    ++iterations;
    for (int i = 0; r_hi > 0.0; ++i) {
      if (i > 200) throw MethodFailure(FailureClass::kNotConverged, t_s, "normal force not bracketed");
      hi *= 4.0;
      r_hi = distance_acceleration(k, d, g, hi);
      ++iterations;
    }
    std::uintmax_t it = static_cast<std::uintmax_t>(max_iterations_);
    const double rtol = rtol_;
    auto tol = [rtol](double a, double b) { return std::abs(b - a) <= rtol * std::abs(b); };
    auto f = [&](double force) { return distance_acceleration(k, d, g, force); };
    const auto br = boost::math::tools::toms748_solve(f, 0.0, hi, r0, r_hi, tol, it);
    iterations += static_cast<long>(it);
    if (static_cast<int>(it) >= max_iterations_ && !tol(br.first, br.second)) {
      throw MethodFailure(FailureClass::kNotConverged, t_s, "normal force iteration did not converge");
    }
    last_force_N_ = 0.5 * (br.first + br.second);
    return last_force_N_;
  }

 private:
  const JeffcottModel* model_;
  double rtol_;
  int max_iterations_;
  mutable double last_force_N_ = 1.0;  // warm start for the bracket
};

template <int kStatorDof>
struct IterationSystem {
  using L = FreeLayout<kStatorDof>;
  const JeffcottModel* model = nullptr;
  const NormalForceSolver* solver = nullptr;
  SpeedSegment segment;
  bool engaged = false;
  long* iterations = nullptr;
  double* rhs_time_s = nullptr;        // profiling only
  double* iteration_time_s = nullptr;  // profiling only

  double normal_force(const Kinematics& k, const DriveState& d, const ContactGeometry& g, double t) const {
    if (!engaged) return 0.0;
    ProfileScope scope(iteration_time_s);
    return solver->solve(k, d, g, t, *iterations);
  }

  void operator()(const typename L::State& x, typename L::State& dxdt, double t) const {
    ProfileScope scope(rhs_time_s);
    const Kinematics k = kinematics_of<kStatorDof>(x);
    const DriveState d = segment.at(t);
    const ContactGeometry g = model->contact_geometry(k, d);
    Vec2 ar, as;
    model->accelerations(k, d, g, normal_force(k, d, g, t), ar, as);
    dxdt.template segment<2>(L::kRotorPos) = k.rotor_vel;
    dxdt.template segment<2>(L::kRotorVel) = ar;
    if constexpr (kStatorDof == 2) {
      dxdt.template segment<2>(L::kStatorPos) = k.stator_vel;
      dxdt.template segment<2>(L::kStatorVel) = as;
    }
  }
};

template <int kStatorDof>
class IterationMethod final : public ContactMethod {
 public:
  using L = FreeLayout<kStatorDof>;
  using State = typename L::State;

  explicit IterationMethod(const Scene& scene)
      : model_(scene.model),
        solver_(&model_, scene.solver.iteration_force_rtol, static_cast<int>(scene.solver.iteration_max_iterations)),
        integrator_(scene.solver.atol, scene.solver.rtol, scene.solver.min_step_s, scene.solver.max_steps),
        initial_step_s_(scene.solver.initial_step_s),
        gap_tolerance_m_(scene.solver.atol),
        guard_(scene.solver.max_events_per_ms) {
    system_.model = &model_;
    system_.solver = &solver_;
    system_.iterations = &stats_.root_iterations;
    if (scene.solver.profile_cost) {
      system_.rhs_time_s = &stats_.rhs_time_s;
      system_.iteration_time_s = &stats_.iteration_time_s;
    }
  }

  void start(double t_s, const Kinematics& k, const SpeedSegment& segment) override {
    system_.segment = segment;
    system_.engaged = false;
    pending_ = false;
    restart_from(t_s, k, initial_step_s_);
  }

  void change_segment(double t_s, const SpeedSegment& segment) override {
    system_.segment = segment;
    ++stats_.restarts;
    if (pending_) {
      pending_ = false;
      // A restart due exactly here (projection, impact) carries over; one
      // later in the step was decided under the old drive and is dropped.
      if (pending_t_ <= t_s) {
        system_.engaged = pending_engaged_;
        restart_from(pending_t_, pending_kin_, integrator_.dt());
        return;
      }
    }
    State x;
    integrator_.state_at(t_s, x);
    restart_from(t_s, kinematics_of<kStatorDof>(x), integrator_.dt());
  }

  void step(double t_limit_s, std::vector<ContactEvent>& events) override {
    if (pending_) {
      // Deferred from the last step, whose dense output served its samples.
      pending_ = false;
      system_.engaged = pending_engaged_;
      restart_from(pending_t_, pending_kin_, integrator_.dt());
    }
    for (;;) {
      integrator_.do_step(system_, stats_);
      if (system_.engaged) break;
      // Free step: reject it while it ends beyond the bore by more than the
      // gap tolerance (no event location in this method).
      const double p = geometry_at(integrator_.t_new()).penetration_m;
      if (p <= gap_tolerance_m_) break;
      integrator_.retreat(0.5 * (integrator_.t_new() - integrator_.t_old()), stats_);
    }
    valid_begin_ = integrator_.t_old();
    valid_end_ = std::min(integrator_.t_new(), t_limit_s);
    if (valid_end_ < integrator_.t_new()) return;  // a segment change restarts here
    State x = integrator_.x_new();
    Kinematics k = kinematics_of<kStatorDof>(x);
    const DriveState d = system_.segment.at(valid_end_);
    ContactGeometry g = model_.contact_geometry(k, d);
    if (system_.engaged) {
      Kinematics held = k;
      project_to_bore(held, g);
      const ContactGeometry gh = model_.contact_geometry(held, d);
      if (solver_.distance_acceleration(held, d, gh, 0.0) <= 0.0) {
        // Lift-off: F_n = 0 already separates. The step's end is kept as
        // integrated (the rotor may have begun to leave within the step).
        guard_.record(valid_end_);
        events.push_back({valid_end_, EventKind::kLiftoff, 0.0, 0.0});
        defer_restart(valid_end_, k, false);
        return;
      }
      // Still held: the drift of this step is projected out.
      stats_.max_constraint_violation_m = std::max(stats_.max_constraint_violation_m, std::abs(g.penetration_m));
      stats_.min_abs_sliding_velocity_m_per_s =
          std::min(stats_.min_abs_sliding_velocity_m_per_s, std::abs(gh.sliding_velocity_m_per_s));
      defer_restart(valid_end_, held, true);
      return;
    }
    if (g.penetration_m < -gap_tolerance_m_) return;  // free flight goes on
    // At the bore within tolerance: impact law, then engage if needed.
    ContactEvent e;
    e.t_s = valid_end_;
    bool settles = true;
    if (g.normal_velocity_m_per_s > 0.0) {
      const ImpactResult ir = apply_impact(model_, g, k);
      settles = ir.settles;
      e.normal_velocity_m_per_s = ir.closing_velocity_m_per_s;
      e.impulse_N_s = ir.normal_impulse_N_s;
    } else if (!(solver_.distance_acceleration(k, d, g, 0.0) > 0.0)) {
      return;  // at the bore, but leaving and not pressed: nothing happens
    }
    g = model_.contact_geometry(k, d);
    const bool sustained = settles && solver_.distance_acceleration(k, d, g, 0.0) > 0.0;
    e.kind = sustained ? EventKind::kTouchdown : EventKind::kGraze;
    guard_.record(valid_end_);
    events.push_back(e);
    if (sustained) project_to_bore(k, g);
    defer_restart(valid_end_, k, sustained);
  }

  double step_begin() const override { return valid_begin_; }
  double step_end() const override { return valid_end_; }

  Sample sample(double t_s) const override {
    State x;
    integrator_.state_at(t_s, x);
    const Kinematics k = kinematics_of<kStatorDof>(x);
    const DriveState d = system_.segment.at(t_s);
    const ContactGeometry g = model_.contact_geometry(k, d);
    long unused = 0;
    const double f = system_.engaged ? solver_.solve(k, d, g, t_s, unused) : 0.0;
    return make_sample(model_, t_s, k, d, f, system_.engaged);
  }

  const RunStats& stats() const override { return stats_; }
  RunStats& mutable_stats() override { return stats_; }

 private:
  ContactGeometry geometry_at(double t_s) const {
    State x;
    integrator_.state_at(t_s, x);
    return model_.contact_geometry(kinematics_of<kStatorDof>(x), system_.segment.at(t_s));
  }

  // Moves both bodies along n so that delta = C, and removes the normal
  // relative velocity, each in inverse proportion to its mass (momentum is
  // kept).
  void project_to_bore(Kinematics& k, const ContactGeometry& g) const {
    const double imr = model_.inv_rotor_mass(), ims = model_.inv_stator_mass(), im = imr + ims;
    k.rotor_pos -= g.penetration_m * (imr / im) * g.normal;
    k.stator_pos += g.penetration_m * (ims / im) * g.normal;
    k.rotor_vel -= g.normal_velocity_m_per_s * (imr / im) * g.normal;
    k.stator_vel += g.normal_velocity_m_per_s * (ims / im) * g.normal;
  }

  void defer_restart(double t_s, const Kinematics& k, bool engaged) {
    pending_ = true;
    pending_t_ = t_s;
    pending_kin_ = k;
    pending_engaged_ = engaged;
  }

  void restart_from(double t_s, const Kinematics& k, double dt) {
    State x;
    store_kinematics<kStatorDof>(k, x);
    integrator_.initialize(system_, x, t_s, dt, stats_);
    valid_begin_ = valid_end_ = t_s;
  }

  JeffcottModel model_;
  NormalForceSolver solver_;
  IterationSystem<kStatorDof> system_;
  DenseDopri5<State> integrator_;
  double initial_step_s_;
  double gap_tolerance_m_;
  ChatterGuard guard_;
  double valid_begin_ = 0.0, valid_end_ = 0.0;
  bool pending_ = false;  // a restart (projection, impact, regime) due at pending_t_
  double pending_t_ = 0.0;
  Kinematics pending_kin_;
  bool pending_engaged_ = false;
  RunStats stats_;
};

}  // namespace

std::unique_ptr<ContactMethod> make_iteration_method(const Scene& scene) {
  if (scene.model.stator_model == StatorModel::kRigid) return std::make_unique<IterationMethod<0>>(scene);
  return std::make_unique<IterationMethod<2>>(scene);
}

}  // namespace rotor_rub::core
