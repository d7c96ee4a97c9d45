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

}  // namespace

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

Eigen::VectorXd full_rub_rates(const TurningRotor& rotor, const StationStator& stator, double C, double f, double w,
                               const Eigen::VectorXd& state, double* normal_force_N, const PenaltyContact* penalty) {
  if (penalty != nullptr) return penalty_rates(rotor, stator, C, f, w, *penalty, state, normal_force_N);
  const RotorMatrices& mat = rotor.matrices;
  const Eigen::MatrixXd& J = rotor.turn;
  const int n = static_cast<int>(mat.M.rows()), nq = coordinates(rotor, stator, nullptr);
  const std::vector<int> free = free_coordinates(rotor);
  const int nf = static_cast<int>(free.size());
  const double theta = state(nq - 1), theta_rate = state(2 * nq - 1);
  const Vec2d u_s = stator.rigid ? Vec2d::Zero() : Vec2d(state(nf), state(nf + 1));
  const Vec2d v_s = stator.rigid ? Vec2d::Zero() : Vec2d(state(nq + nf), state(nq + nf + 1));
  const Vec2d nrm(std::cos(theta), std::sin(theta)), tng = kTurn2 * nrm;
  // The rotor's coordinates and rates, the station's from the stator and theta.
  Eigen::VectorXd v(n), vd(n);
  for (int i = 0; i < nf; ++i) {
    v(free[i]) = state(i);
    vd(free[i]) = state(nq + i);
  }
  const Vec2d st = u_s + C * nrm, st_rate = v_s + C * theta_rate * tng;
  v(rotor.station_x) = st.x(), v(rotor.station_y) = st.y();
  vd(rotor.station_x) = st_rate.x(), vd(rotor.station_y) = st_rate.y();
  // The station's acceleration: u_s'' + C theta'' t - C theta'^2 n.
  Eigen::MatrixXd st_cols(n, 2);
  st_cols.col(0) = mat.M.col(rotor.station_x);
  st_cols.col(1) = mat.M.col(rotor.station_y);
  const Eigen::MatrixXd CG = mat.C + w * mat.G;
  Eigen::VectorXd rotor_rest = w * w * rotor.unbalance_kg_m - mat.M * (2.0 * w * (J * vd) - w * w * v) -
                               CG * (vd + w * (J * v)) - mat.K * v + st_cols * (C * theta_rate * theta_rate * nrm);
  // Unknowns: [free accelerations, u_s'' (elastic), theta'', N].
  const int unknowns = nq + 1, th = nq - 1, nn = nq;
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n + (stator.rigid ? 0 : 2), unknowns);
  Eigen::VectorXd b(a.rows());
  for (int i = 0; i < nf; ++i) a.block(0, i, n, 1) = mat.M.col(free[i]);
  if (!stator.rigid) a.block(0, nf, n, 2) = st_cols;
  a.block(0, th, n, 1) = st_cols * (C * tng);
  const Vec2d push = nrm + f * tng;  // the contact force on the rotor is -N push
  a(rotor.station_x, nn) = push.x();
  a(rotor.station_y, nn) = push.y();
  b.head(n) = rotor_rest;
  if (!stator.rigid) {
    const double ms = stator.mass_kg, cs = stator.damping_N_s_per_m, ks = stator.stiffness_N_per_m;
    a.block<2, 2>(n, nf) = ms * Eigen::Matrix2d::Identity();
    a.block<2, 1>(n, nn) = -push;
    b.tail<2>() = -(ms * (2.0 * w * (kTurn2 * v_s) - w * w * u_s) + cs * (v_s + w * (kTurn2 * u_s)) + ks * u_s);
  }
  const Eigen::VectorXd x = a.fullPivLu().solve(b);
  if (normal_force_N != nullptr) *normal_force_N = x(nn);
  Eigen::VectorXd rates(2 * nq);
  rates.head(nq) = state.tail(nq);
  rates.tail(nq) = x.head(nq);
  return rates;
}

FullRubStability linearised_full_rub(const TurningRotor& rotor, const StationStator& stator, double C, double f,
                                     double w, const Eigen::VectorXd& guess, const PenaltyContact* penalty) {
  const int nq = coordinates(rotor, stator, penalty);
  FullRubStability s;
  // Each coordinate's scale: its own size, at least the clearance's (or a
  // modal coordinate's typical size); a rate's, w times that.
  Eigen::VectorXd scale(2 * nq);
  for (int j = 0; j < nq; ++j) {
    const bool angle = penalty == nullptr && j == nq - 1;
    scale(j) = angle ? 1.0 : std::max(std::abs(guess(j)), 1e-3 * C);
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
    for (int j = 0; j < nq; ++j) {
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
  s.jacobian.resize(2 * nq, 2 * nq);
  for (int j = 0; j < 2 * nq; ++j) {
    const double h = 1e-6 * scale(j);
    Eigen::VectorXd up = s.state, down = s.state;
    up(j) += h;
    down(j) -= h;
    s.jacobian.col(j) = (full_rub_rates(rotor, stator, C, f, w, up, nullptr, penalty) -
                         full_rub_rates(rotor, stator, C, f, w, down, nullptr, penalty)) /
                        (2.0 * h);
  }
  const Eigen::VectorXcd lambda = Eigen::EigenSolver<Eigen::MatrixXd>(s.jacobian).eigenvalues();
  s.eigenvalues.assign(lambda.data(), lambda.data() + lambda.size());
  std::sort(s.eigenvalues.begin(), s.eigenvalues.end(),
            [](cd a, cd b) { return a.real() != b.real() ? a.real() > b.real() : a.imag() > b.imag(); });
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
  penalty.damping_N_s_per_m = contact_damping_N_s_per_m(JeffcottModel(p));
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
