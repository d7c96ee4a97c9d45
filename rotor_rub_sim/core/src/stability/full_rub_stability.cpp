#include "rotor_rub_sim/core/full_rub_stability.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/model.hpp"

namespace rotor_rub::core {
namespace {

using cd = std::complex<double>;
using Vec2d = Eigen::Vector2d;

const Eigen::Matrix2d kTurn2 = (Eigen::Matrix2d() << 0.0, -1.0, 1.0, 0.0).finished();

// The coordinates but the station's, in order.
std::vector<int> free_coordinates(const TurningRotor& r) {
  std::vector<int> out;
  for (int i = 0; i < r.matrices.M.rows(); ++i) {
    if (i != r.station_x && i != r.station_y) out.push_back(i);
  }
  return out;
}

// q's size: the free coordinates, the stator's two when elastic, theta (the
// rigid contact); every coordinate and the stator's (the penalty contact).
int coordinates(const TurningRotor& r, const StationStator& s, const PenaltyContact* penalty) {
  const int n = static_cast<int>(r.matrices.M.rows()), stator = s.rigid ? 0 : 2;
  return penalty != nullptr ? n + stator : n - 2 + stator + 1;
}

// The penalty contact's rates: the rotor's and the stator's equations with
// the contact force of the state (no constraint).
Eigen::VectorXd penalty_rates(const TurningRotor& rotor, const StationStator& stator, double C, double f, double w,
                              const PenaltyContact& penalty, const Eigen::VectorXd& state, double* normal_force_N) {
  const RotorMatrices& mat = rotor.matrices;
  const Eigen::MatrixXd& J = rotor.turn;
  const int n = static_cast<int>(mat.M.rows()), nq = coordinates(rotor, stator, &penalty);
  const Eigen::VectorXd v = state.head(n), vd = state.segment(nq, n);
  const Vec2d u_s = stator.rigid ? Vec2d::Zero() : Vec2d(state(n), state(n + 1));
  const Vec2d v_s = stator.rigid ? Vec2d::Zero() : Vec2d(state(nq + n), state(nq + n + 1));
  const Vec2d gap = Vec2d(v(rotor.station_x), v(rotor.station_y)) - u_s;
  const Vec2d gap_rate = Vec2d(vd(rotor.station_x), vd(rotor.station_y)) - v_s;
  const Vec2d nrm = gap.normalized(), tng = kTurn2 * nrm;
  // n . (the gap's rate in the casing's frame) = n . gap_rate: n . J gap = 0.
  const double N = penalty.stiffness_N_per_m * (gap.norm() - C) + penalty.damping_N_s_per_m * nrm.dot(gap_rate);
  if (normal_force_N != nullptr) *normal_force_N = N;
  const Vec2d push = N * (nrm + f * tng);  // the contact force on the rotor is -push
  Eigen::VectorXd force = w * w * rotor.unbalance_kg_m - mat.M * (2.0 * w * (J * vd) - w * w * v) -
                          (mat.C + w * mat.G) * (vd + w * (J * v)) - mat.K * v;
  force(rotor.station_x) -= push.x();
  force(rotor.station_y) -= push.y();
  Eigen::VectorXd rates(2 * nq);
  rates.head(nq) = state.tail(nq);
  rates.segment(nq, n) = mat.M.ldlt().solve(force);
  if (!stator.rigid) {
    const double ms = stator.mass_kg, cs = stator.damping_N_s_per_m, ks = stator.stiffness_N_per_m;
    rates.tail<2>() =
        (push - ms * (2.0 * w * (kTurn2 * v_s) - w * w * u_s) - cs * (v_s + w * (kTurn2 * u_s)) - ks * u_s) / ms;
  }
  return rates;
}

// Whether J commutes with every matrix (isotropy) to 1e-9 of its size.
void check_isotropic(const TurningRotor& r, const char* what) {
  const Eigen::MatrixXd& J = r.turn;
  for (const auto* m : {&r.matrices.M, &r.matrices.K, &r.matrices.C, &r.matrices.G}) {
    const double scale = std::max(m->cwiseAbs().maxCoeff(), 1e-300);
    if ((J * *m - *m * J).cwiseAbs().maxCoeff() > 1e-9 * scale) {
      throw std::invalid_argument(std::string(what) +
                                  ": not isotropic (its matrices do not commute with the rotation: bearings or seals "
                                  "with kxx != kyy or kxy != -kyx, say); the full rub is then no equilibrium of the "
                                  "turning frame");
    }
  }
}

// Balances a in place (Parlett and Reinsch: D^-1 a D with D a diagonal of
// powers of 2, each row's and column's off-diagonal norms made alike), and
// returns D. A flexible rotor's Jacobian spans its modes' w^2, 1e0 to 1e10;
// unbalanced, the eigensolver's rounding moved a flutter's growth rate by
// hundreds per second (TheSealRotorsRunsFollowTheLinearisation).
Eigen::VectorXd balance(Eigen::MatrixXd& a) {
  const Eigen::Index n = a.rows();
  Eigen::VectorXd d = Eigen::VectorXd::Ones(n);
  for (bool done = false; !done;) {
    done = true;
    for (Eigen::Index i = 0; i < n; ++i) {
      double c = a.col(i).cwiseAbs().sum() - std::abs(a(i, i)), r = a.row(i).cwiseAbs().sum() - std::abs(a(i, i));
      if (c == 0.0 || r == 0.0) continue;
      const double s = c + r;
      double f = 1.0;
      while (c < r / 2.0) f *= 2.0, c *= 4.0;
      while (c > r * 2.0) f /= 2.0, c /= 4.0;
      if ((c + r) / f < 0.95 * s) {
        done = false;
        d(i) *= f;
        a.row(i) /= f;
        a.col(i) *= f;
      }
    }
  }
  return d;
}

}  // namespace

std::vector<std::complex<double>> balanced_eigenvalues(const Eigen::MatrixXd& a) {
  Eigen::MatrixXd b = a;
  balance(b);
  const Eigen::VectorXcd lambda = Eigen::EigenSolver<Eigen::MatrixXd>(b, false).eigenvalues();
  std::vector<std::complex<double>> out(lambda.data(), lambda.data() + lambda.size());
  std::sort(out.begin(), out.end(),
            [](cd x, cd y) { return x.real() != y.real() ? x.real() > y.real() : x.imag() > y.imag(); });
  return out;
}

Eigen::VectorXd linear_response(const Eigen::MatrixXd& a, const Eigen::VectorXd& x0, double t_s) {
  Eigen::MatrixXd b = a;
  const Eigen::VectorXd d = balance(b);
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(b);
  const Eigen::MatrixXcd v = eig.eigenvectors();
  const Eigen::VectorXcd c = v.fullPivLu().solve(x0.cwiseQuotient(d).cast<cd>());
  Eigen::VectorXcd y = Eigen::VectorXcd::Zero(a.rows());
  for (Eigen::Index k = 0; k < a.rows(); ++k) y += v.col(k) * (c(k) * std::exp(eig.eigenvalues()(k) * t_s));
  return y.real().cwiseProduct(d);
}

StationStator station_stator(const ModelParameters& p) {
  StationStator s;
  s.rigid = p.stator_model == StatorModel::kRigid;
  s.mass_kg = p.stator_mass_kg;
  s.stiffness_N_per_m = p.stator_stiffness_N_per_m;
  s.damping_N_s_per_m = p.stator_damping_N_s_per_m;
  return s;
}

TurningRotor turning_rotor(const ModelParameters& p) {
  TurningRotor r;
  const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
  r.matrices.M = p.rotor_mass_kg * I;
  r.matrices.K = p.rotor_stiffness_N_per_m * I;
  r.matrices.C = p.rotor_damping_N_s_per_m * I;
  r.matrices.G = Eigen::Matrix2d::Zero();
  r.turn = kTurn2;
  r.unbalance_kg_m =
      p.rotor_mass_kg * p.eccentricity_m * Vec2d(std::cos(p.unbalance_phase_rad), std::sin(p.unbalance_phase_rad));
  return r;
}

TurningRotor turning_rotor(const RotorMatrices& m, const std::vector<RotorUnbalance>& unbalances, int station_node) {
  TurningRotor r;
  r.matrices = m;
  const int n = static_cast<int>(m.M.rows());
  r.turn = Eigen::MatrixXd::Zero(n, n);
  for (int base = 0; base < n; base += 2) r.turn.block<2, 2>(base, base) = kTurn2;  // (x, y), (alpha, beta)
  check_isotropic(r, "the rotor");
  r.unbalance_kg_m = Eigen::VectorXd::Zero(n);
  for (const RotorUnbalance& u : unbalances) {
    r.unbalance_kg_m(dof_index(u.node, kDofX)) += u.me_kg_m * std::cos(u.phase_rad);
    r.unbalance_kg_m(dof_index(u.node, kDofY)) += u.me_kg_m * std::sin(u.phase_rad);
  }
  r.station_x = dof_index(station_node, kDofX);
  r.station_y = dof_index(station_node, kDofY);
  return r;
}

TurningRotor turning_rotor(const ReducedRotor& reduced, const RotorMatrices& m,
                           const std::vector<RotorUnbalance>& unbalances) {
  const TurningRotor full = turning_rotor(m, unbalances, reduced.station_node);
  const Eigen::MatrixXd& E = reduced.expansion;
  TurningRotor r;
  r.matrices = reduced.matrices;
  // J in the basis: M_r^-1 E^T M J E, exact when the basis holds the rotation.
  r.turn = reduced.matrices.M.ldlt().solve(E.transpose() * m.M * full.turn * E);
  if ((E * r.turn - full.turn * E).cwiseAbs().maxCoeff() > 1e-8 * E.cwiseAbs().maxCoeff()) {
    throw std::invalid_argument("the reduced rotor's basis does not hold the rotation (its planes are no twins)");
  }
  check_isotropic(r, "the reduced rotor");
  r.unbalance_kg_m = E.transpose() * full.unbalance_kg_m;
  r.station_x = ReducedRotor::kStationX;
  r.station_y = ReducedRotor::kStationY;
  return r;
}

namespace {

// The rigid contact's equations at a state, solved: A x = b with x = [free
// accelerations, u_s'' (elastic), theta'', N] (full_rub_rates).
struct ConstrainedSolve {
  Eigen::MatrixXd a, station_columns;  // A; M's columns of the station's x and y
  Eigen::VectorXd x;
  Vec2d nrm, tng;
};

ConstrainedSolve solve_constrained(const TurningRotor& rotor, const StationStator& stator, double C, double f, double w,
                                   const Eigen::VectorXd& state) {
  const RotorMatrices& mat = rotor.matrices;
  const Eigen::MatrixXd& J = rotor.turn;
  const int n = static_cast<int>(mat.M.rows()), nq = coordinates(rotor, stator, nullptr);
  const std::vector<int> free = free_coordinates(rotor);
  const int nf = static_cast<int>(free.size());
  const double theta = state(nq - 1), theta_rate = state(2 * nq - 1);
  const Vec2d u_s = stator.rigid ? Vec2d::Zero() : Vec2d(state(nf), state(nf + 1));
  const Vec2d v_s = stator.rigid ? Vec2d::Zero() : Vec2d(state(nq + nf), state(nq + nf + 1));
  ConstrainedSolve c;
  c.nrm = Vec2d(std::cos(theta), std::sin(theta));
  c.tng = kTurn2 * c.nrm;
  // The rotor's coordinates and rates, the station's from the stator and theta.
  Eigen::VectorXd v(n), vd(n);
  for (int i = 0; i < nf; ++i) {
    v(free[i]) = state(i);
    vd(free[i]) = state(nq + i);
  }
  const Vec2d st = u_s + C * c.nrm, st_rate = v_s + C * theta_rate * c.tng;
  v(rotor.station_x) = st.x(), v(rotor.station_y) = st.y();
  vd(rotor.station_x) = st_rate.x(), vd(rotor.station_y) = st_rate.y();
  // The station's acceleration: u_s'' + C theta'' t - C theta'^2 n.
  c.station_columns.resize(n, 2);
  c.station_columns.col(0) = mat.M.col(rotor.station_x);
  c.station_columns.col(1) = mat.M.col(rotor.station_y);
  const Eigen::MatrixXd CG = mat.C + w * mat.G;
  const Eigen::VectorXd rotor_rest = w * w * rotor.unbalance_kg_m - mat.M * (2.0 * w * (J * vd) - w * w * v) -
                                     CG * (vd + w * (J * v)) - mat.K * v +
                                     c.station_columns * (C * theta_rate * theta_rate * c.nrm);
  const int th = nq - 1, nn = nq;
  c.a = Eigen::MatrixXd::Zero(n + (stator.rigid ? 0 : 2), nq + 1);
  Eigen::VectorXd b(c.a.rows());
  for (int i = 0; i < nf; ++i) c.a.block(0, i, n, 1) = mat.M.col(free[i]);
  if (!stator.rigid) c.a.block(0, nf, n, 2) = c.station_columns;
  c.a.block(0, th, n, 1) = c.station_columns * (C * c.tng);
  const Vec2d push = c.nrm + f * c.tng;  // the contact force on the rotor is -N push
  c.a(rotor.station_x, nn) = push.x();
  c.a(rotor.station_y, nn) = push.y();
  b.head(n) = rotor_rest;
  if (!stator.rigid) {
    const double ms = stator.mass_kg, cs = stator.damping_N_s_per_m, ks = stator.stiffness_N_per_m;
    c.a.block<2, 2>(n, nf) = ms * Eigen::Matrix2d::Identity();
    c.a.block<2, 1>(n, nn) = -push;
    b.tail<2>() = -(ms * (2.0 * w * (kTurn2 * v_s) - w * w * u_s) + cs * (v_s + w * (kTurn2 * u_s)) + ks * u_s);
  }
  c.x = c.a.fullPivLu().solve(b);
  return c;
}

// The rigid contact's Jacobian of [q; q'] at a state, analytic: the
// equations are linear in every coordinate but theta, whose terms are
// differentiated by hand, so no difference step meets a stiff mode's
// rounding (TheSealRotorsRunsFollowTheLinearisation). d x = A^-1 (d b - d A x).
Eigen::MatrixXd rigid_jacobian(const TurningRotor& rotor, const StationStator& stator, double C, double f, double w,
                               const Eigen::VectorXd& state) {
  const RotorMatrices& mat = rotor.matrices;
  const Eigen::MatrixXd& J = rotor.turn;
  const int n = static_cast<int>(mat.M.rows()), nq = coordinates(rotor, stator, nullptr);
  const std::vector<int> free = free_coordinates(rotor);
  const int nf = static_cast<int>(free.size()), th = nq - 1, nn = nq;
  const double theta_rate = state(2 * nq - 1);
  const ConstrainedSolve c = solve_constrained(rotor, stator, C, f, w, state);
  const int sx = rotor.station_x, sy = rotor.station_y;
  // d v and d v' as maps of d [q; q'].
  Eigen::MatrixXd pv = Eigen::MatrixXd::Zero(n, 2 * nq), pvd = Eigen::MatrixXd::Zero(n, 2 * nq);
  for (int i = 0; i < nf; ++i) {
    pv(free[i], i) = 1.0;
    pvd(free[i], nq + i) = 1.0;
  }
  if (!stator.rigid) {
    pv(sx, nf) = pv(sy, nf + 1) = 1.0;
    pvd(sx, nq + nf) = pvd(sy, nq + nf + 1) = 1.0;
  }
  pv(sx, th) = C * c.tng.x(), pv(sy, th) = C * c.tng.y();
  pvd(sx, nq + th) = C * c.tng.x(), pvd(sy, nq + th) = C * c.tng.y();
  pvd(sx, th) = -C * theta_rate * c.nrm.x(), pvd(sy, th) = -C * theta_rate * c.nrm.y();
  const Eigen::MatrixXd CG = mat.C + w * mat.G;
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(c.a.rows(), 2 * nq);
  d.topRows(n) = (w * w * mat.M - mat.K - w * CG * J) * pv - (2.0 * w * mat.M * J + CG) * pvd;
  d.block(0, th, n, 1) += c.station_columns * (C * theta_rate * theta_rate * c.tng);
  d.block(0, nq + th, n, 1) += c.station_columns * (2.0 * C * theta_rate * c.nrm);
  if (!stator.rigid) {
    const double ms = stator.mass_kg, cs = stator.damping_N_s_per_m, ks = stator.stiffness_N_per_m;
    const Eigen::Matrix2d I2 = Eigen::Matrix2d::Identity();
    d.block<2, 2>(n, nf) = (ms * w * w - ks) * I2 - cs * w * kTurn2;
    d.block<2, 2>(n, nq + nf) = -2.0 * w * ms * kTurn2 - cs * I2;
  }
  // The columns of A that turn with theta: the one of theta'' (C t at the
  // station) and the one of N (push = n + f t).
  const Vec2d dpush = c.tng - f * c.nrm;
  Eigen::VectorXd da_x = Eigen::VectorXd::Zero(c.a.rows());
  da_x.head(n) = c.station_columns * (-C * c.nrm) * c.x(th);
  da_x(sx) += dpush.x() * c.x(nn);
  da_x(sy) += dpush.y() * c.x(nn);
  if (!stator.rigid) da_x.tail<2>() = -dpush * c.x(nn);
  d.col(th) -= da_x;
  const Eigen::MatrixXd dx = c.a.fullPivLu().solve(d);
  Eigen::MatrixXd jac = Eigen::MatrixXd::Zero(2 * nq, 2 * nq);
  jac.topRightCorner(nq, nq).setIdentity();
  jac.bottomRows(nq) = dx.topRows(nq);
  return jac;
}

}  // namespace

Eigen::VectorXd full_rub_rates(const TurningRotor& rotor, const StationStator& stator, double C, double f, double w,
                               const Eigen::VectorXd& state, double* normal_force_N, const PenaltyContact* penalty) {
  if (penalty != nullptr) return penalty_rates(rotor, stator, C, f, w, *penalty, state, normal_force_N);
  const int nq = coordinates(rotor, stator, nullptr);
  const ConstrainedSolve c = solve_constrained(rotor, stator, C, f, w, state);
  if (normal_force_N != nullptr) *normal_force_N = c.x(nq);
  Eigen::VectorXd rates(2 * nq);
  rates.head(nq) = state.tail(nq);
  rates.tail(nq) = c.x.head(nq);
  return rates;
}

FullRubStability linearised_full_rub(const TurningRotor& rotor, const StationStator& stator, double C, double f,
                                     double w, const Eigen::VectorXd& guess, const PenaltyContact* penalty) {
  const int nq = coordinates(rotor, stator, penalty);
  FullRubStability s;
  // Each coordinate's scale: its own size, at least the clearance (a stiff
  // mode's coordinate is tiny at the rest point, and a difference step
  // scaled by it would drown in the rounding of its k/m times it: the
  // rates are linear in every coordinate but theta, so a step of C 1e-6 is
  // exact for them); a rate's, w times that.
  Eigen::VectorXd scale(2 * nq);
  for (int j = 0; j < nq; ++j) {
    const bool angle = penalty == nullptr && j == nq - 1;
    scale(j) = angle ? 1.0 : std::max(std::abs(guess(j)), C);
    scale(nq + j) = w * scale(j);
  }
  auto accelerations = [&](const Eigen::VectorXd& positions) {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * nq);
    x.head(nq) = positions;
    return Eigen::VectorXd(full_rub_rates(rotor, stator, C, f, w, x, nullptr, penalty).tail(nq));
  };
  // Newton on the rest point: accelerations(q) = 0 at zero rates.
  // Done when every acceleration is below 1e-12 of w^2 times its
  // coordinate's scale (a closed form's guess already is; near a fold the
  // Jacobian is nearly singular and Newton would only amplify rounding), or
  // when the step is below 1e-12 of the scale (a stiff mode's acceleration
  // keeps the rounding of k/m times its coordinate).
  Eigen::VectorXd q = guess.head(nq);
  for (int it = 0;; ++it) {
    const Eigen::VectorXd r = accelerations(q);
    if ((r.cwiseQuotient(w * w * scale.head(nq))).cwiseAbs().maxCoeff() < 1e-12) break;
    if (it == 50) throw std::runtime_error("full rub: Newton on the turning frame's rest point did not converge");
    Eigen::MatrixXd jac(nq, nq);
    if (penalty == nullptr) {
      Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * nq);
      x.head(nq) = q;
      jac = rigid_jacobian(rotor, stator, C, f, w, x).bottomLeftCorner(nq, nq);
    }
    for (int j = 0; penalty != nullptr && j < nq; ++j) {
      const double h = 1e-6 * scale(j);
      Eigen::VectorXd up = q, down = q;
      up(j) += h;
      down(j) -= h;
      jac.col(j) = (accelerations(up) - accelerations(down)) / (2.0 * h);
    }
    const Eigen::VectorXd dq = jac.fullPivLu().solve(-r);
    q += dq;
    if ((dq.cwiseQuotient(scale.head(nq))).cwiseAbs().maxCoeff() < 1e-12) break;  // a stiff mode's own rounding
  }
  s.state = Eigen::VectorXd::Zero(2 * nq);
  s.state.head(nq) = q;
  full_rub_rates(rotor, stator, C, f, w, s.state, &s.normal_force_N, penalty);
  if (penalty != nullptr) {
    const int n = static_cast<int>(rotor.matrices.M.rows());
    s.station_m = cd(q(rotor.station_x), q(rotor.station_y));
    s.stator_m = stator.rigid ? cd(0.0) : cd(q(n), q(n + 1));
  } else {
    const Vec2d u_s = stator.rigid ? Vec2d::Zero() : Vec2d(q(nq - 3), q(nq - 2));
    s.stator_m = cd(u_s.x(), u_s.y());
    s.station_m = s.stator_m + C * std::polar(1.0, q(nq - 1));
  }
  if (penalty == nullptr) {
    s.jacobian = rigid_jacobian(rotor, stator, C, f, w, s.state);
  } else {
    s.jacobian.resize(2 * nq, 2 * nq);
  }
  for (int j = 0; penalty != nullptr && j < 2 * nq; ++j) {
    const double h = 1e-6 * scale(j);
    Eigen::VectorXd up = s.state, down = s.state;
    up(j) += h;
    down(j) -= h;
    s.jacobian.col(j) = (full_rub_rates(rotor, stator, C, f, w, up, nullptr, penalty) -
                         full_rub_rates(rotor, stator, C, f, w, down, nullptr, penalty)) /
                        (2.0 * h);
  }
  s.eigenvalues = balanced_eigenvalues(s.jacobian);
  return s;
}

std::vector<FullRubStability> full_rub_stability(const ModelParameters& p, double w, bool penalty_contact) {
  if (p.gravity_m_per_s2 != 0.0) {
    throw std::invalid_argument("full rub stability: gravity_m_per_s2 must be 0 (it breaks the circular symmetry)");
  }
  if (p.drive_model != DriveModel::kPrescribed) {
    throw std::invalid_argument("full rub stability: the prescribed drive only (drive_model prescribed)");
  }
  if (p.stator_model == StatorModel::kRigid && (p.stator_offset_x_m != 0.0 || p.stator_offset_y_m != 0.0)) {
    throw std::invalid_argument(
        "full rub stability: stator_offset_x_m and stator_offset_y_m must be 0 (an offset bore breaks the circular "
        "symmetry)");
  }
  const TurningRotor rotor = turning_rotor(p);
  const StationStator stator = station_stator(p);
  PenaltyContact penalty;
  penalty.stiffness_N_per_m = p.contact_stiffness_N_per_m;
  penalty.damping_N_s_per_m = contact_damping_N_s_per_m(StationModel(p));
  std::vector<FullRubStability> out;
  for (const FullRub& rub : synchronous_full_rub(p, w)) {
    const int nq = coordinates(rotor, stator, penalty_contact ? &penalty : nullptr);
    Eigen::VectorXd guess = Eigen::VectorXd::Zero(2 * nq);
    if (penalty_contact) {
      // The rigid rest point with the bore moved out by the overlap N / k_c.
      const cd gap = rub.rotor_m - rub.stator_m;
      const cd rotor_m = rub.stator_m + gap * (1.0 + rub.normal_force_N / (penalty.stiffness_N_per_m * std::abs(gap)));
      guess.head<2>() << rotor_m.real(), rotor_m.imag();
      if (!stator.rigid) guess.segment<2>(2) << rub.stator_m.real(), rub.stator_m.imag();
    } else {
      if (!stator.rigid) guess.head<2>() << rub.stator_m.real(), rub.stator_m.imag();
      guess(nq - 1) = std::arg(rub.rotor_m - rub.stator_m);
    }
    out.push_back(linearised_full_rub(rotor, stator, p.clearance_m, p.friction_coefficient, w, guess,
                                      penalty_contact ? &penalty : nullptr));
  }
  return out;
}

std::vector<FullRubStability> full_rub_stability(const RotorMatrices& m, int station_node,
                                                 const std::vector<RotorUnbalance>& unbalances,
                                                 const StationStator& stator, double C, double f, double w,
                                                 const ReducedRotor* reduced) {
  const TurningRotor rotor =
      reduced != nullptr ? turning_rotor(*reduced, m, unbalances) : turning_rotor(m, unbalances, station_node);
  const int nq = coordinates(rotor, stator, nullptr);
  const std::vector<int> free = free_coordinates(rotor);
  std::vector<FullRubStability> out;
  for (const FlexibleFullRub& rub : synchronous_full_rub(m, station_node, unbalances, stator, C, f, w)) {
    // The full model's rest point at spin angle 0, in the rotor's coordinates
    // (a reduced rotor's: the M-orthogonal projection onto its basis).
    const Eigen::VectorXd full = rub.response.real();
    const Eigen::VectorXd v =
        reduced != nullptr
            ? Eigen::VectorXd(reduced->matrices.M.ldlt().solve(reduced->expansion.transpose() * m.M * full))
            : full;
    Eigen::VectorXd guess = Eigen::VectorXd::Zero(2 * nq);
    for (std::size_t i = 0; i < free.size(); ++i) guess(static_cast<Eigen::Index>(i)) = v(free[i]);
    if (!stator.rigid) {
      guess(nq - 3) = rub.stator_m.real();
      guess(nq - 2) = rub.stator_m.imag();
    }
    guess(nq - 1) = std::arg(rub.station_m - rub.stator_m);
    out.push_back(linearised_full_rub(rotor, stator, C, f, w, guess));
  }
  return out;
}

std::vector<std::complex<double>> rigid_full_rub_eigenvalues(const ModelParameters& p, double w, const FullRub& rub) {
  const double m = p.rotor_mass_kg, C = p.clearance_m, f = p.friction_coefficient;
  const double phi = std::arg(rub.rotor_m) - p.unbalance_phase_rad;
  const double a = m * C, b = (p.rotor_damping_N_s_per_m + 2.0 * f * m * w) * C;
  const double c = m * p.eccentricity_m * w * w * (std::cos(phi) - f * std::sin(phi));
  const cd root = std::sqrt(cd(b * b - 4.0 * a * c));
  std::vector<cd> out{(-b + root) / (2.0 * a), (-b - root) / (2.0 * a)};
  std::sort(out.begin(), out.end(),
            [](cd x, cd y) { return x.real() != y.real() ? x.real() > y.real() : x.imag() > y.imag(); });
  return out;
}

}  // namespace rotor_rub::core
