// The stiff option (integrator key rosenbrock4: the penalty method, the
// switching and iteration methods' free flight): RODASP,
// Steinebach's L-stable, stiffly accurate Rosenbrock 4(3) with six stages and
// a third-order continuous extension, on fixed-size Eigen types (a flexible
// rotor's: dynamic within a fixed bound, below).
//
// Why not Boost.Odeint's rosenbrock4 (used here until issue 13): it is Hairer
// and Wanner's RODAS, and on this model it
// * carries a wrong time-derivative weight (d4 = +0.0362; rodas.f and the
//   row sums of its own Gamma give -0.0362), which drops it to first order on
//   any non-autonomous system (every scene: the unbalance turns with time);
// * even corrected, loses order where the contact's slow mode
//   (-k_c / c_c ~ -6.3e3 1/s on the paper scene) meets steps with h |lambda|
//   of 1 to 100: RODAS is not exact on the Prothero-Robinson problem
//   y' = lambda (y - g(t)) + g'(t); its steps shrank 3x per decade of
//   tolerance there (h^1 behaviour). RODASP adds the conditions that remove
//   this order reduction (Steinebach 1995, "Order-reduction of ROW-methods
//   for DAEs and method of lines applications", Preprint 1741, TH Darmstadt).
// * works on ublas containers with a dynamic LU.
// test_rodasp.cpp measures RODASP's orders on closed forms and odeint's
// steps beside its own on the Prothero-Robinson problem.
//
// Form (Hairer and Wanner II, IV.7): with E = I - h gamma J,
//   E u_i = f(t + a_i h, y + h sum_j alpha_ij K_j) + sum_j gt_ij K_j + g_i h f_t,
//   K_i = u_i - sum_j gt_ij K_j    (gt = Gamma_offdiag / gamma),
//   y1 = y + h sum b_i K_i, the embedded y1^ = y + h sum bh_i K_i,
//   y(t + s h) = y + s h sum K_i (b_i + (s - 1)(c_i + s d_i)).
// The Jacobian J = df/dy and f_t = df/dt come from the system in closed form
// where it gives them (kAnalyticJacobian: under the prescribed drive, the
// penalty method's, penalty_system.hpp, and free flight's, free_jacobian in
// rotor_model.hpp; 6 right-hand sides an accepted step, 5 a rejected one),
// else are forward differences of the same right-hand side (jacobian()): n +
// 2 more a step for n states (a motor drive's). A flexible rotor's state is
// dynamic within a bound (state_layout.hpp), J and its LU are allocated once
// (initialize()): no allocation per step.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

#include "integrators/step_ends.hpp"
#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/run_types.hpp"

namespace rotor_rub::core {

struct RodaspTableau {
  static constexpr int kStages = 6;
  static constexpr double kGamma = 0.25;
  using Table = std::array<std::array<double, kStages>, kStages>;
  Table alpha{};  // stage abscissae weights
  Table gt{};     // Gamma's off-diagonal over gamma
  std::array<double, kStages> a{}, g{}, b{}, bh{}, c{}, d{};

  RodaspTableau() {
    // Steinebach's coefficients in the (alpha, beta = alpha + Gamma) form.
    Table beta{};
    alpha[1] = {0.75};
    alpha[2] = {8.6120400814152190e-2, 0.1238795991858478};
    alpha[3] = {0.7749345355073236, 0.1492651549508680, -0.2941996904581916};
    alpha[4] = {5.308746682646142, 1.330892140037269, -5.374137811655562, -0.2655010110278497};
    alpha[5] = {-1.764437648774483, -0.4747565572063027, 2.369691846915802, 0.6195023590649829, 0.25};
    beta[2] = {-0.049392, -0.014112};
    beta[3] = {-0.4820494693877561, -0.1008795555555556, 0.9267290249433117};
    beta[4] = {-1.764437648774483, -0.4747565572063027, 2.369691846915802, 0.6195023590649829};
    beta[5] = {-8.0368370789113464e-2, -5.6490613592447572e-2, 0.4882856300427991, 0.5057162114816189,
               -0.1071428571428569};
    for (int j = 0; j < kStages - 1; ++j) {
      b[j] = beta[5][j];
      bh[j] = beta[4][j];
    }
    b[5] = kGamma;
    bh[4] = kGamma;
    bh[5] = 0.0;
    for (int i = 0; i < kStages; ++i) {
      double gamma_row = kGamma;
      for (int j = 0; j < i; ++j) {
        a[i] += alpha[i][j];
        gt[i][j] = (beta[i][j] - alpha[i][j]) / kGamma;
        gamma_row += beta[i][j] - alpha[i][j];
      }
      g[i] = gamma_row;
    }
    c = {-40.98639964388325, -10.36668980524365, 44.66751816647147, 4.13001572709988, 2.55555555555556, 0.0};
    d = {73.75018659483291, 18.54063799119389, -81.66902074619779, -6.84402606205123, -3.77777777777778, 0.0};
  }
};

// Every system DenseRodasp steps states its optional hooks, each a
// static constexpr bool (a missing or misspelled one fails to compile, so
// no hook is dropped silently when a name drifts; a hook set true whose
// function is missing fails too):
//   kAnalyticJacobian: J = df/dx and df/dt in closed form,
//     void jacobian(const State& x, double t, Matrix& J, State& dfdt) const;
//   kSecondOrderJacobian (with kAnalyticJacobian): the state's first half
//     the positions q, its second their velocities v = q' (J = [0 I; A B],
//     df/dt = [0; g]): each stage's E u = r then takes one system of half
//     the size, (I - tau B - tau^2 A) u_v = r_v + tau A r_p with u_p = r_p +
//     tau u_v (tau = h gamma): a 4x4 LU for the elastic stator's 8 states,
//     an eighth of the full one's work. A state of dynamic size (a flexible
//     rotor's) is [q (kFixedDof), q', xi (n), xi'], its positions q and xi:
//     static constexpr int kFixedDof;
//   kOwnErrorNorm: a state that is not the one its tolerances are meant for
//     (the penalty method's polar coordinates) measures a step's error itself,
//     double error_norm(const State& err, const State& x0, const State& x1, double atol, double rtol) const;

template <class State>
class DenseRodasp {
 public:
  static constexpr Integrator kScheme = Integrator::kRosenbrock4;
  static constexpr int kSize = State::RowsAtCompileTime;
  static constexpr int kStages = RodaspTableau::kStages;
  // A flexible rotor's state is of dynamic size: its matrices are allocated
  // once, at the first initialize() (a fixed maximum would put megabytes on
  // the stack), and keep their storage (test_allocations).
  using Matrix = std::conditional_t<kSize == Eigen::Dynamic, Eigen::MatrixXd, Eigen::Matrix<double, kSize, kSize>>;

  DenseRodasp(double atol, double rtol, double min_step_s, long max_steps)
      : atol_(atol), rtol_(rtol), min_step_s_(min_step_s), max_steps_(max_steps) {}

  template <class System>
  void initialize(System& /*sys*/, const State& x, double t_s, double dt_s, RunStats& /*stats*/) {
    x_old_ = x_new_ = x;
    f0_ = dfdt_ = step_ = cont_c_ = cont_d_ = State::Zero(x.size());
    jac_ = Matrix::Zero(x.size(), x.size());
    if constexpr (System::kSecondOrderJacobian && kSize == Eigen::Dynamic) {
      block_solver_.resize(System::kFixedDof, static_cast<int>(x.size()));
    }
    t_old_ = t_new_ = t_s;
    dt_ = dt_s;
    err_old_ = 0.0;
    dt_old_ = 0.0;
    first_ = true;
    last_rejected_ = false;
  }

  template <class System>
  void do_step(System& sys, RunStats& stats) {
    x_old_ = x_new_;
    t_old_ = t_new_;
    const double t = t_old_;
    sys(x_old_, f0_, t);
    ++stats.rhs_evals;
    jacobian(sys, t, stats);

    for (;;) {
      check_step_budget(stats, max_steps_, dt_, min_step_s_, t);
      const double h = dt_;
      const double e = attempt(sys, h, stats);
      const State x1 = x_old_ + step_;
      if (!(e <= 1.0) || !x1.allFinite()) {
        ++stats.rejected_steps;
        // A non-finite trial shrinks as far as a rejection can (step_ends.hpp).
        dt_ = std::isfinite(e) && x1.allFinite() ? h * std::clamp(0.9 * std::pow(e, -0.25), 0.2, 1.0)
                                                 : step_after_non_finite(h, min_step_s_, t);
        last_rejected_ = true;
        continue;
      }
      // Gustafsson's predictive controller (as odeint's rosenbrock4_controller).
      double fac = std::clamp(std::pow(e, 0.25) / 0.9, 1.0 / 6.0, 5.0);
      if (!first_) {
        const double pred = std::clamp((dt_old_ / h) * std::pow(e * e / err_old_, 0.25) / 0.9, 1.0 / 6.0, 5.0);
        fac = std::max(fac, pred);
      }
      first_ = false;
      dt_old_ = h;
      err_old_ = std::max(0.01, e);
      double next = h / fac;
      if (last_rejected_) next = std::min(next, h);
      last_rejected_ = false;
      accept(x1, t + h);
      dt_ = next;
      break;
    }
    ++stats.steps;
    if (!x_new_.allFinite()) throw MethodFailure(FailureClass::kDiverged, t_new_, "non-finite state");
  }

  // Ends the last step at t_s in (t_old, t_new] by taking it again from its
  // start with the step t_s - t_old (one more step's work, no error control:
  // it is shorter than the accepted one). A restart at an event then starts
  // from a step's end, not from the continuous extension, whose stability
  // function between the steps exceeds 1 for stiff components (1.6 at s
  // 0.1-0.25 as h lambda -> -inf): a damped stiff transient would be
  // restarted amplified.
  template <class System>
  void end_step_at(System& sys, double t_s, RunStats& stats) {
    if (!(t_s > t_old_) || t_s >= t_new_) return;
    attempt(sys, t_s - t_old_, stats);
    accept(State(x_old_ + step_), t_s);
  }

  void state_at(double t_s, State& x) const {
    if (t_new_ == t_old_) {
      x = x_new_;
      return;
    }
    const double h = t_new_ - t_old_;
    const double s = (t_s - t_old_) / h;
    // y + s h sum K_i (b_i + (s - 1)(c_i + s d_i)), with h sum b_i K_i = x_new - x_old.
    x = x_old_ + s * ((x_new_ - x_old_) + (s - 1.0) * h * (cont_c_ + s * cont_d_));
  }

  // Undo the last accepted step and retry it with dt_s (a method's own
  // rejection: the iteration method's free step that passed the bore).
  void retreat(double dt_s, RunStats& stats) {
    x_new_ = x_old_;
    t_new_ = t_old_;
    dt_ = dt_s;
    --stats.steps;
    ++stats.rejected_steps;
  }

  const State& x_old() const { return x_old_; }
  const State& x_new() const { return x_new_; }
  double t_old() const { return t_old_; }
  double t_new() const { return t_new_; }
  double dt() const { return dt_; }
  void set_dt(double dt_s) { dt_ = dt_s; }
  // Caps the next step's proposal, as StepEnds::limit_dt (a NaN cap: none).
  void limit_dt(double max_dt_s) {
    if (dt_ > max_dt_s) dt_ = max_dt_s;
  }

 private:
  static const RodaspTableau& tableau() {
    static const RodaspTableau t;
    return t;
  }

  // Without a closed form (kAnalyticJacobian), J = df/dx at (x_old, t)
  // by forward differences, the state's step 1e-7
  // of the component kept within [1e-13, 1e-7] (an angle that keeps growing,
  // a motor's spin, does not get a coarse one). f_t = df/dt by a central
  // difference, its step cbrt(eps) max(|t|, 1e-3): a forward difference's
  // error (w h_t / 2 relative, 6e-7 at 130 rad/s) enters every stage and
  // held the step's local error at second order below w h ~ 0.2
  // (test_rodasp.cpp measures the orders); the central one's is
  // (w h_t)^2 / 6 (1e-8).
  template <class System>
  void jacobian(System& sys, double t, RunStats& stats) {
    ++stats.jacobian_evals;
    if constexpr (System::kAnalyticJacobian) {
      sys.jacobian(x_old_, t, jac_, dfdt_);
      return;
    }
    State f1, f2;
    const Eigen::Index n = x_old_.size();
    for (Eigen::Index j = 0; j < n; ++j) {
      const double h = 1e-7 * std::clamp(std::abs(x_old_[j]), 1e-6, 1.0);
      State xp = x_old_;
      xp[j] += h;
      sys(xp, f1, t);
      jac_.col(j) = (f1 - f0_) / (xp[j] - x_old_[j]);
    }
    const double ht = std::cbrt(std::numeric_limits<double>::epsilon()) * std::max(std::abs(t), 1e-3);
    sys(x_old_, f1, t + ht);
    sys(x_old_, f2, t - ht);
    dfdt_ = (f1 - f2) / (2.0 * ht);
    stats.rhs_evals += n + 2;
  }

  // One trial step of size h from (x_old, t_old): the stages, step_ (the
  // increment) and the error norm.
  template <class System>
  double attempt(System& sys, double h, RunStats& stats) {
    static_assert(!System::kSecondOrderJacobian || System::kAnalyticJacobian, "a second-order J is a closed form");
    if constexpr (System::kSecondOrderJacobian && kSize == Eigen::Dynamic) {
      block_solver_.factor(jac_, h * RodaspTableau::kGamma);
      return attempt_with(sys, h, block_solver_, stats);
    } else if constexpr (System::kSecondOrderJacobian) {
      return attempt_with(sys, h, SecondOrderSolver(jac_, h * RodaspTableau::kGamma), stats);
    } else {
      full_lu_.compute(Matrix::Identity(jac_.rows(), jac_.cols()) - (h * RodaspTableau::kGamma) * jac_);
      return attempt_with(sys, h, FullSolver{full_lu_}, stats);
    }
  }

  // E^-1 r, E = I - tau J, by one LU of E (full_lu_, factored by attempt()).
  struct FullSolver {
    const Eigen::PartialPivLU<Matrix>& lu;
    State solve(const State& r) const { return lu.solve(r); }
  };
  // The same for J = [0 I; A B] (kSecondOrderJacobian).
  struct SecondOrderSolver {
    static_assert(kSize % 2 == 0, "[q, v]: as many velocities as positions");
    static constexpr int kHalf = kSize / 2;
    using Half = Eigen::Matrix<double, kHalf, 1>;
    using HalfMatrix = Eigen::Matrix<double, kHalf, kHalf>;
    HalfMatrix a;
    double tau;
    Eigen::PartialPivLU<HalfMatrix> lu;
    SecondOrderSolver(const Matrix& jac, double tau_s)
        : a(jac.template bottomLeftCorner<kHalf, kHalf>()),
          tau(tau_s),
          lu(HalfMatrix::Identity() - tau_s * jac.template bottomRightCorner<kHalf, kHalf>() - (tau_s * tau_s) * a) {}
    State solve(const State& r) const {
      const Half rp = r.template head<kHalf>();
      const Half uv = lu.solve(r.template tail<kHalf>() + tau * (a * rp));
      State u;
      u << rp + tau * uv, uv;
      return u;
    }
  };

  // The same for a state of dynamic size [q (fixed_dof), q', xi (n), xi']:
  // the positions and velocities gathered by index (loops: Eigen's indexed
  // views copy their indices to the heap), the matrices sized once (resize)
  // and refactored in place (no allocation per step: test_allocations).
  struct BlockSecondOrderSolver {
    using Half = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, State::MaxRowsAtCompileTime / 2, 1>;
    Eigen::VectorXi pos, vel;
    Eigen::MatrixXd a, e;
    Eigen::PartialPivLU<Eigen::MatrixXd> lu;
    double tau = 0.0;
    int fixed = -1;  // the fixed part's positions pos and vel were built for
    void resize(int fixed_dof, int size) {
      const int n = (size - 2 * fixed_dof) / 2, half = fixed_dof + n;
      if (pos.size() == half && fixed == fixed_dof) return;  // a restart: sized already
      fixed = fixed_dof;
      pos.resize(half);
      vel.resize(half);
      for (int i = 0; i < fixed_dof; ++i) {
        pos[i] = i;
        vel[i] = fixed_dof + i;
      }
      for (int j = 0; j < n; ++j) {
        pos[fixed_dof + j] = 2 * fixed_dof + j;
        vel[fixed_dof + j] = 2 * fixed_dof + n + j;
      }
      a.resize(half, half);
      e.resize(half, half);
      lu = Eigen::PartialPivLU<Eigen::MatrixXd>(half);
    }
    void factor(const Matrix& jac, double tau_s) {
      tau = tau_s;
      const Eigen::Index half = pos.size();
      for (Eigen::Index j = 0; j < half; ++j) {
        for (Eigen::Index i = 0; i < half; ++i) {
          a(i, j) = jac(vel[i], pos[j]);
          e(i, j) = -tau_s * (jac(vel[i], vel[j]) + tau_s * a(i, j));
        }
        e(j, j) += 1.0;
      }
      lu.compute(e);
    }
    State solve(const State& r) const {
      const Eigen::Index half = pos.size();
      Half rp(half), rv(half);
      for (Eigen::Index i = 0; i < half; ++i) {
        rp[i] = r[pos[i]];
        rv[i] = r[vel[i]];
      }
      // rv += tau A rp, by columns (Eigen's product of these types warns
      // falsely under GCC 12 of a read past the vector).
      for (Eigen::Index j = 0; j < half; ++j) rv += (tau * rp[j]) * a.col(j);
      const Half uv = lu.solve(rv);
      State u(r.size());
      for (Eigen::Index i = 0; i < half; ++i) {
        u[pos[i]] = rp[i] + tau * uv[i];
        u[vel[i]] = uv[i];
      }
      return u;
    }
  };

  template <class System, class Solver>
  double attempt_with(System& sys, double h, const Solver& solver, RunStats& stats) {
    const RodaspTableau& tab = tableau();
    const double t = t_old_;
    {
      for (int i = 0; i < kStages; ++i) {
        State y = x_old_;
        State sum = State::Zero(x_old_.size());
        for (int j = 0; j < i; ++j) {
          y += (h * tab.alpha[i][j]) * k_[j];
          sum += tab.gt[i][j] * k_[j];
        }
        State f;
        if (i == 0) {
          f = f0_;
        } else {
          sys(y, f, t + tab.a[i] * h);
          ++stats.rhs_evals;
        }
        k_[i] = solver.solve(f + sum + (tab.g[i] * h) * dfdt_) - sum;
      }
    }
    State err = State::Zero(x_old_.size());
    step_.setZero(x_old_.size());
    for (int i = 0; i < kStages; ++i) {
      step_ += tab.b[i] * k_[i];
      err += (tab.b[i] - tab.bh[i]) * k_[i];
    }
    step_ *= h;
    err *= h;
    const State x1 = x_old_ + step_;
    // The RMS norm of odeint's controllers, scaled by atol + rtol max(|x0|, |x1|),
    // or the system's own (kOwnErrorNorm).
    if constexpr (System::kOwnErrorNorm) {
      return sys.error_norm(err, x_old_, x1, atol_, rtol_);
    } else {
      return std::sqrt((err.array() / (atol_ + rtol_ * x_old_.array().abs().max(x1.array().abs()))).square().mean());
    }
  }

  // Takes the last attempt as the step to t_s: its end and the continuous
  // extension's two correction vectors.
  void accept(const State& x1, double t_s) {
    const RodaspTableau& tab = tableau();
    x_new_ = x1;
    t_new_ = t_s;
    cont_c_.setZero(x1.size());
    cont_d_.setZero(x1.size());
    for (int i = 0; i < kStages; ++i) {
      cont_c_ += tab.c[i] * k_[i];
      cont_d_ += tab.d[i] * k_[i];
    }
  }

  double atol_, rtol_;
  double min_step_s_;
  long max_steps_;
  std::array<State, kStages> k_{};
  State f0_, dfdt_, step_;  // sized by initialize()
  Matrix jac_;
  Eigen::PartialPivLU<Matrix> full_lu_;  // E's LU when the Jacobian is full (FullSolver)
  BlockSecondOrderSolver block_solver_;  // a dynamic state's second-order solve
  State x_old_, x_new_, cont_c_, cont_d_;
  double t_old_ = 0.0, t_new_ = 0.0, dt_ = 1e-5;
  double err_old_ = 0.0, dt_old_ = 0.0;
  bool first_ = true, last_rejected_ = false;
};

template <class Integrator>
struct is_implicit : std::false_type {};
template <class State>
struct is_implicit<DenseRodasp<State>> : std::true_type {};

// Ends an implicit integrator's last step at t_s, at a speed segment's end or
// a live change (DenseRodasp::end_step_at); an explicit scheme's dense output
// is its step's own, and nothing is taken again.
template <class Integrator, class System>
void end_step_if_implicit(Integrator& integrator, System& sys, double t_s, RunStats& stats) {
  if constexpr (is_implicit<Integrator>::value) integrator.end_step_at(sys, t_s, stats);
}

}  // namespace rotor_rub::core
