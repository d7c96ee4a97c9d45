#include "rotor_rub_sim/core/penalty_method.hpp"

#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/cost_profiler.hpp"
#include "rotor_rub_sim/core/dense_dopri5.hpp"
#include "rotor_rub_sim/core/dense_rk4.hpp"
#include "rotor_rub_sim/core/dense_rosenbrock4.hpp"
#include "rotor_rub_sim/core/event_location.hpp"
#include "rotor_rub_sim/core/sample_builder.hpp"

namespace rotor_rub::core {
namespace {

// The penalty contact law (contact_law.hpp): a spring-dashpot normal force,
// never pulling (clamped at 0), and a tangential damper capped at the cone.
struct PenaltyLaw {
  double stiffness_N_per_m;
  double damping_N_s_per_m;
  double friction_coefficient;
  double tangential_damping_N_s_per_m;
  double normal(const ContactGeometry& g) const {
    if (g.penetration_m <= 0.0) return 0.0;
    return std::max(0.0, stiffness_N_per_m * g.penetration_m + damping_N_s_per_m * g.normal_velocity_m_per_s);
  }
  double tangential(const ContactGeometry& g, double normal_N) const {
    return penalty_friction_N(friction_coefficient, normal_N, tangential_damping_N_s_per_m, g.sliding_velocity_m_per_s);
  }
};

template <int kStatorDof, bool kMotor>
struct PenaltySystem {
  using L = FreeLayout<kStatorDof, kMotor>;
  using State = typename L::State;
  const JeffcottModel* model;
  PenaltyLaw law;
  SpeedSegment segment;
  double* rhs_time_s = nullptr;  // profiling only

  void operator()(const State& x, State& dxdt, double t) const {
    ProfileScope scope(rhs_time_s);
    const Kinematics k = kinematics_of<kStatorDof, kMotor>(x);
    const DriveState reference = segment.at(t);
    const DriveState d = model->drive_at(k, reference);
    const ContactGeometry g = model->contact_geometry(k, d);
    const double fn = law.normal(g);
    const Accelerations a = model->accelerations(k, d, g, fn, law.tangential(g, fn));
    dxdt.template segment<2>(L::kRotorPos) = k.rotor_vel;
    dxdt.template segment<2>(L::kRotorVel) = a.rotor;
    if constexpr (kStatorDof == 2) {
      dxdt.template segment<2>(L::kStatorPos) = k.stator_vel;
      dxdt.template segment<2>(L::kStatorVel) = a.stator;
    }
    spin_derivative<L>(*model, k, reference, a.spin_rad_per_s2, dxdt);
  }
};

template <class Integrator>
Integrator make_integrator(const SolverSettings& s) {
  if constexpr (is_fixed_step<Integrator>::value) {
    return Integrator(s.fixed_step_s, s.max_steps);
  } else {
    return Integrator(s.atol, s.rtol, s.min_step_s, s.max_steps);
  }
}

template <int kStatorDof, bool kMotor, class Integrator>
class PenaltyMethod final : public ContactMethod {
 public:
  using L = FreeLayout<kStatorDof, kMotor>;
  using State = typename L::State;

  explicit PenaltyMethod(const Scene& scene)
      : model_(scene.model),
        integrator_(make_integrator<Integrator>(scene.solver)),
        initial_step_s_(scene.solver.initial_step_s) {
    system_.model = &model_;
    system_.law = {scene.model.contact_stiffness_N_per_m, contact_damping_N_s_per_m(model_),
                   scene.model.friction_coefficient, tangential_damping_N_s_per_m(model_)};
    if (scene.solver.profile_cost) system_.rhs_time_s = &stats_.rhs_time_s;
  }

  void start(double t_s, const Kinematics& k, const SpeedSegment& segment) override {
    State x;
    store_kinematics<kStatorDof, kMotor>(k, x);
    system_.segment = segment;
    integrator_.initialize(system_, x, t_s, initial_step_s_, stats_);
    valid_end_ = t_s;
    penetration_end_ = model_.contact_geometry(k, model_.drive_at(k, segment.at(t_s))).penetration_m;
  }

  void change_segment(double t_s, const SpeedSegment& segment) override {
    State x;
    integrator_.state_at(t_s, x);
    const double dt = integrator_.dt();
    start(t_s, kinematics_of<kStatorDof, kMotor>(x), segment);
    integrator_.set_dt(dt);
    ++stats_.restarts;
  }

  void step(double t_limit_s, std::vector<ContactEvent>& events) override {
    integrator_.do_step(system_, stats_);
    valid_end_ = std::min(integrator_.t_new(), t_limit_s);
    const double p0 = penetration_end_;
    const double p1 = penetration_at(valid_end_);
    penetration_end_ = p1;
    // Report the crossings of delta = C (the kink of the force law).
    if ((p0 <= 0.0) != (p1 <= 0.0)) {
      auto f = [this](double t) { return penetration_at(t); };
      const double te = locate_event(f, integrator_.t_old(), p0, valid_end_, p1, stats_);
      ContactEvent e;
      e.t_s = te;
      e.kind = p1 > 0.0 ? EventKind::kTouchdown : EventKind::kLiftoff;
      if (e.kind == EventKind::kTouchdown) e.normal_velocity_m_per_s = geometry_at(te).normal_velocity_m_per_s;
      events.push_back(e);
    }
    if (p1 > 0.0) {
      const ContactGeometry g = geometry_at(valid_end_);
      stats_.min_abs_sliding_velocity_m_per_s =
          std::min(stats_.min_abs_sliding_velocity_m_per_s, std::abs(g.sliding_velocity_m_per_s));
    }
  }

  double step_begin() const override { return integrator_.t_old(); }
  double step_end() const override { return valid_end_; }

  Sample sample(double t_s) const override {
    State x;
    integrator_.state_at(t_s, x);
    const Kinematics k = kinematics_of<kStatorDof, kMotor>(x);
    const DriveState d = model_.drive_at(k, system_.segment.at(t_s));
    const ContactGeometry g = model_.contact_geometry(k, d);
    const double fn = system_.law.normal(g);
    const double ft = system_.law.tangential(g, fn);
    Sample s = make_sample(model_, t_s, k, d, fn, ft, g.penetration_m > 0.0);
    s.sticking = s.in_contact && std::abs(ft) < system_.law.friction_coefficient * fn;
    return s;
  }

  const RunStats& stats() const override { return stats_; }
  RunStats& mutable_stats() override { return stats_; }

 private:
  ContactGeometry geometry_at(double t_s) const {
    State x;
    integrator_.state_at(t_s, x);
    const Kinematics k = kinematics_of<kStatorDof, kMotor>(x);
    return model_.contact_geometry(k, model_.drive_at(k, system_.segment.at(t_s)));
  }
  double penetration_at(double t_s) const { return geometry_at(t_s).penetration_m; }

  JeffcottModel model_;
  PenaltySystem<kStatorDof, kMotor> system_;
  Integrator integrator_;
  double initial_step_s_;
  double penetration_end_ = -1.0;  // at valid_end_
  double valid_end_ = 0.0;
  RunStats stats_;
};

template <int kStatorDof, bool kMotor>
std::unique_ptr<ContactMethod> make_for_dof(const Scene& scene) {
  using State = typename FreeLayout<kStatorDof, kMotor>::State;
  switch (scene.solver.integrator) {
    case Integrator::kRosenbrock4:
      return std::make_unique<PenaltyMethod<kStatorDof, kMotor, DenseRosenbrock4<State>>>(scene);
    case Integrator::kRk4:
      return std::make_unique<PenaltyMethod<kStatorDof, kMotor, DenseRk4<State>>>(scene);
    case Integrator::kDopri5:
      break;
    case Integrator::kRkf78:  // validate_scene refuses it: the penalty contact is stiff
      throw std::invalid_argument("integrator rkf78 is not accepted with method penalty");
  }
  return std::make_unique<PenaltyMethod<kStatorDof, kMotor, DenseDopri5<State>>>(scene);
}

}  // namespace

std::unique_ptr<ContactMethod> make_penalty_method(const Scene& scene) {
  const bool rigid = scene.model.stator_model == StatorModel::kRigid;
  if (scene.model.drive_model == DriveModel::kMotor)
    return rigid ? make_for_dof<0, true>(scene) : make_for_dof<2, true>(scene);
  return rigid ? make_for_dof<0, false>(scene) : make_for_dof<2, false>(scene);
}

}  // namespace rotor_rub::core
