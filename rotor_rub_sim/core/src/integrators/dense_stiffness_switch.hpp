// The integrator key dop853_rosenbrock4 in free flight: dop853 while the
// tolerance sets its steps, RODASP while dop853's stability does (a flexible
// rotor's highest modes kept), as LSODA switches between Adams and BDF.
// Neither is the faster on every rotor: RODASP's steps are not bound by the
// modes kept, but each costs a Jacobian's LU and ringing modes or short
// flights keep them short (docs/rotors.md, "Speed at many modes").
//
// dop853 to RODASP: Hairer's stiffness test in dop853 (Solving ODEs II,
// IV.2): h rho, rho the Lipschitz quotient of the accepted step's last stage
// (Dop853::h_rho), at or above kStiffHRho on `needed_` accepted steps
// (kNonStiffSteps below it clear the count); then, as LSODA weighs its two
// methods' steps by their costs, a probe of kWindowSteps RODASP steps taken
// on the side (rodasp_pays()) decides: RODASP takes the flight if its mean
// step is longer than dop853's stiff ones by kCostRatio, a RODASP step's
// cost in dop853 steps (a Jacobian's LU besides its 6 stages). A probe that
// loses leaves dop853's flight as it was: a switch there and back would hand
// dop853 a state whose stiff modes carry RODASP's errors, and an undamped
// mode rung at the tolerance's level holds dop853's steps to its accuracy
// (StiffnessSwitch.RodaspNoFasterThanDop853LeavesTheFlightAlone).
// RODASP to dop853: each window of kWindowSteps RODASP steps is weighed the
// same way (the rotor's contacts may ring its modes); short flights count
// against RODASP, as they should: each of the switching method's RODASP
// flights begins with the first trial step (its restarts).
// Each probe or window lost doubles the stiff steps the next try needs (up
// to kMaxNeeded), so that a rotor on which neither wins pays for few
// probes; a window that keeps RODASP resets it.
// A switch happens at the start of the next step or restart, so that the
// last step's dense output stays the one a method scans. The engine and the
// counts carry over a restart (initialize()): stiffness is the rotor's, so a
// stiff rotor stays on RODASP across flights, however short.
// StiffnessSwitch.* (test_stiffness_switch.cpp) hold it.
#pragma once

#include <algorithm>

#include "integrators/dense_high_order.hpp"
#include "integrators/dense_rodasp.hpp"
#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

template <class Layout>
class DenseStiffnessSwitch {
 public:
  using State = typename Layout::State;
  // dop853's stability boundary is 6.0 on the imaginary axis (a lightly
  // damped mode) and 6.4 on the negative real one; Hairer's 6.1 is for the
  // real axis, so a mode's h rho at the boundary would not pass it.
  static constexpr double kStiffHRho = 5.0;
  static constexpr int kStiffSteps = 15;      // dop853's NSTIFF test count: the first try's `needed_`
  static constexpr int kNonStiffSteps = 6;    // dop853's: non-stiff steps that clear the count
  static constexpr int kMaxNeeded = 15 << 6;  // after six failed tries
  static constexpr int kWindowSteps = 15;
  // A RODASP step's cost in dop853 steps: 1.55 to 1.7 measured on three
  // flexible rotors at 20 to 24 planar modes (docs/rotors.md, "Speed at many
  // modes"; 2.2 at 32, where RODASP's steps are 20 times longer); its
  // restarts' short first steps are in the window's mean.
  static constexpr double kCostRatio = 1.6;

  DenseStiffnessSwitch(double atol, double rtol, double min_step_s, long max_steps)
      : explicit_(atol, rtol, min_step_s, max_steps), implicit_(atol, rtol, min_step_s, max_steps) {}

  // Starts the engine of the next step at x (a switch due at the last step's end is taken here).
  template <class System>
  void initialize(System& sys, const State& x, double t_s, double dt_s, RunStats& stats) {
    if (x.size() != sized_) {
      // RODASP's matrices sized at the start, not at the first probe: no allocation mid-run (test_allocations).
      RunStats none;
      implicit_.initialize(sys, x, t_s, dt_s, none);
      sized_ = x.size();
    }
    if (switch_due_) {
      implicit_on_ = !implicit_on_;
      ++stats.integrator_switches;
      // RODASP's proposal knows nothing of dop853's stability: kept to dop853's stiff steps.
      if (!implicit_on_) dt_s = std::min(dt_s, explicit_h_s_);
      stiff_ = non_stiff_ = window_steps_ = 0;
      stiff_s_ = window_s_ = 0.0;
    }
    switch_due_ = false;
    on([&](auto& i) { i.initialize(sys, x, t_s, dt_s, stats); });
  }

  template <class System>
  void do_step(System& sys, RunStats& stats) {
    if (switch_due_) {
      handover_ = x_new();  // the last step's end (no allocation but the first)
      initialize(sys, handover_, t_new(), dt(), stats);
    }
    if (implicit_on_) {
      implicit_.do_step(sys, stats);
      window_s_ += implicit_.t_new() - implicit_.t_old();
      if (++window_steps_ < kWindowSteps) return;
      if (window_s_ / window_steps_ < cost_ratio<System>() * explicit_h_s_) {
        switch_due_ = true;
        needed_ = std::min(2 * needed_, kMaxNeeded);
      } else {
        needed_ = kStiffSteps;
      }
      window_steps_ = 0;
      window_s_ = 0.0;
      return;
    }
    explicit_.do_step(sys, stats);
    if (!(explicit_.h_rho() >= kStiffHRho)) {
      if (++non_stiff_ >= kNonStiffSteps) {
        stiff_ = 0;
        stiff_s_ = 0.0;
      }
      return;
    }
    non_stiff_ = 0;
    stiff_s_ += explicit_.t_new() - explicit_.t_old();
    if (++stiff_ < needed_) return;
    explicit_h_s_ = stiff_s_ / stiff_;
    stiff_ = 0;
    stiff_s_ = 0.0;
    if (rodasp_pays(sys, stats)) {
      switch_due_ = true;
    } else {
      needed_ = std::min(2 * needed_, kMaxNeeded);
    }
  }

  // RODASP's last step ended at t_s (DenseRodasp::end_step_at); dop853's
  // dense output is its step's own.
  template <class System>
  void end_step_at(System& sys, double t_s, RunStats& stats) {
    if (implicit_on_) implicit_.end_step_at(sys, t_s, stats);
  }

  // The engine of the last step, and of the next step or restart.
  Integrator scheme_now() const { return implicit_on_ ? Integrator::kRosenbrock4 : Integrator::kDop853; }
  Integrator scheme_next() const {
    return implicit_on_ != switch_due_ ? Integrator::kRosenbrock4 : Integrator::kDop853;
  }
  void state_at(double t_s, State& x) const {
    on([&](const auto& i) { i.state_at(t_s, x); });
  }
  void retreat(double dt_s, RunStats& stats) {
    on([&](auto& i) { i.retreat(dt_s, stats); });
  }
  void limit_dt(double max_dt_s) {
    on([&](auto& i) { i.limit_dt(max_dt_s); });
  }
  const State& x_old() const {
    return on([](const auto& i) -> const State& { return i.x_old(); });
  }
  const State& x_new() const {
    return on([](const auto& i) -> const State& { return i.x_new(); });
  }
  double t_old() const {
    return on([](const auto& i) { return i.t_old(); });
  }
  double t_new() const {
    return on([](const auto& i) { return i.t_new(); });
  }
  double dt() const {
    return on([](const auto& i) { return i.dt(); });
  }

 private:
  // The probe: kWindowSteps RODASP steps from dop853's last step's end, on
  // the side (the flight goes on from that end, on whichever engine wins);
  // their work is the run's, their steps are not. True when RODASP's mean
  // step is longer than dop853's stiff ones by a RODASP step's cost.
  template <class System>
  bool rodasp_pays(System& sys, RunStats& stats) {
    RunStats probe;
    const double t0_s = explicit_.t_new();
    implicit_.initialize(sys, explicit_.x_new(), t0_s, explicit_.dt(), probe);
    bool stepped = true;
    try {
      for (int i = 0; i < kWindowSteps; ++i) implicit_.do_step(sys, probe);
    } catch (const MethodFailure&) {
      stepped = false;  // no step RODASP could take there: dop853 goes on
    }
    stats.rhs_evals += probe.rhs_evals;
    stats.jacobian_evals += probe.jacobian_evals;
    return stepped && (implicit_.t_new() - t0_s) / kWindowSteps >= cost_ratio<System>() * explicit_h_s_;
  }

  // A RODASP step's cost in dop853 steps: kCostRatio with the Jacobian in
  // closed form; a differenced one (under a motor drive) adds n + 2
  // derivative evaluations a step, each a twelfth of a dop853 step (11
  // stages and the end's derivative).
  template <class System>
  double cost_ratio() const {
    if constexpr (System::kAnalyticJacobian) {
      return kCostRatio;
    } else {
      return kCostRatio + static_cast<double>(sized_ + 2) / 12.0;
    }
  }

  template <class F>
  decltype(auto) on(F&& f) {
    return implicit_on_ ? f(implicit_) : f(explicit_);
  }
  template <class F>
  decltype(auto) on(F&& f) const {
    return implicit_on_ ? f(implicit_) : f(explicit_);
  }

  DenseDop853<Layout> explicit_;
  DenseRodasp<State> implicit_;
  bool implicit_on_ = false;
  bool switch_due_ = false;
  int needed_ = kStiffSteps;       // stiff dop853 steps that switch to RODASP
  int stiff_ = 0, non_stiff_ = 0;  // dop853's stiff steps, and its non-stiff ones since the last
  double stiff_s_ = 0.0;           // [s] the stiff steps' length
  double explicit_h_s_ = 0.0;      // [s] their mean at the switch to RODASP
  int window_steps_ = 0;           // RODASP's steps in the window, and their length [s]
  double window_s_ = 0.0;
  Eigen::Index sized_ = -1;  // the state's size RODASP's matrices have
  State handover_;           // do_step(): the last step's end at a switch
};

template <class Layout>
struct is_implicit<DenseStiffnessSwitch<Layout>> : std::true_type {};

}  // namespace rotor_rub::core
