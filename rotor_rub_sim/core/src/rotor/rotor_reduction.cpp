#include "rotor_rub_sim/core/rotor_reduction.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace rotor_rub::core {
namespace {

// The x-z plane's DOFs (x and beta of every node) and the y-z plane's twins
// (y and alpha): a shape (x, beta) in the first is (y, alpha) = (x, -beta)
// in the second, the same shape turned 90 deg about the axis.
struct Planes {
  std::vector<int> x_plane, y_plane;
  std::vector<double> twin_sign;  // y_plane[k] = twin_sign[k] * x_plane[k]'s value
};

Planes planes_of(const FeRotor& rotor) {
  Planes p;
  for (int node = 0; node < rotor.nodes(); ++node) {
    p.x_plane.push_back(dof_index(node, kDofX));
    p.y_plane.push_back(dof_index(node, kDofY));
    p.twin_sign.push_back(1.0);
    p.x_plane.push_back(dof_index(node, kDofBeta));
    p.y_plane.push_back(dof_index(node, kDofAlpha));
    p.twin_sign.push_back(-1.0);
  }
  for (int node = rotor.nodes(); node < rotor.nodes() + rotor.support_nodes(); ++node) {
    p.x_plane.push_back(rotor.translation_dof(node, kDofX));  // a support node's x and y alone
    p.y_plane.push_back(rotor.translation_dof(node, kDofY));
    p.twin_sign.push_back(1.0);
  }
  return p;
}

}  // namespace

RotorReduction::RotorReduction(const FeRotor& rotor, const RotorMatrices& m, int station_node, int planar_modes)
    : station_node_(station_node), m_(m) {
  const int nodes = rotor.nodes();
  if (station_node < 0 || station_node >= nodes) {
    throw std::invalid_argument("rub station: node " + std::to_string(station_node) +
                                " is out of range; accepted: 0 to " + std::to_string(nodes - 1));
  }
  if (planar_modes < 1 || planar_modes > max_planar_modes(rotor)) {
    throw std::invalid_argument("retained modes: " + std::to_string(planar_modes) +
                                " is out of range; accepted: 1 to " + std::to_string(max_planar_modes(rotor)) +
                                " (the rotor's planar DOFs)");
  }
  if (m.M.rows() != rotor.dofs()) {
    throw std::invalid_argument("reduce_rotor: the matrices have " + std::to_string(m.M.rows()) + " DOF, the rotor " +
                                std::to_string(rotor.dofs()) + ": not assembled from it");
  }
  const Planes planes = planes_of(rotor);
  x_plane_ = planes.x_plane;
  y_plane_ = planes.y_plane;
  twin_sign_ = planes.twin_sign;
  for (int node = 0; node < nodes; ++node) node_z_m_.push_back(rotor.node_z_m(node));
  const int np = static_cast<int>(planes.x_plane.size());
  // Each plane's stiffness and mass in planar indices (the y-z plane's with
  // its twin signs), symmetric: a static shape is the symmetric part's.
  auto plane_block = [&](const Eigen::MatrixXd& x, bool y_plane) {
    Eigen::MatrixXd out(np, np);
    const auto& dofs = y_plane ? planes.y_plane : planes.x_plane;
    for (int a = 0; a < np; ++a) {
      for (int b = 0; b < np; ++b) {
        const double sign = y_plane ? planes.twin_sign[a] * planes.twin_sign[b] : 1.0;
        out(a, b) = sign * x(dofs[a], dofs[b]);
      }
    }
    return Eigen::MatrixXd(0.5 * (out + out.transpose()));
  };
  const Eigen::MatrixXd k_x = plane_block(m.K, false), k_y = plane_block(m.K, true);
  const Eigen::MatrixXd m_plane = 0.5 * (plane_block(m.M, false) + plane_block(m.M, true));
  // The station's x is planar index 2 * station_node; the interior is the rest.
  const int station = 2 * station_node;
  std::vector<int> interior;
  for (int a = 0; a < np; ++a) {
    if (a != station) interior.push_back(a);
  }
  const int ni = np - 1;
  auto interior_block = [&](const Eigen::MatrixXd& x) {
    Eigen::MatrixXd out(ni, ni);
    for (int a = 0; a < ni; ++a) {
      for (int b = 0; b < ni; ++b) out(a, b) = x(interior[a], interior[b]);
    }
    return out;
  };
  const Eigen::MatrixXd m_ii = interior_block(m_plane);
  const Eigen::MatrixXd k_x_ii = interior_block(k_x), k_y_ii = interior_block(k_y);
  // The static shape of a unit station displacement (the interior's part) in
  // a plane of stiffness k.
  auto constraint_shape = [&](const Eigen::MatrixXd& k, const Eigen::MatrixXd& k_ii, const char* plane) {
    const Eigen::LLT<Eigen::MatrixXd> llt(k_ii);
    // A pivot at roundoff is as singular as a negative one.
    if (llt.info() != Eigen::Success || !(llt.rcond() > 1e-14)) {
      throw std::invalid_argument("rub station: node " + std::to_string(station_node) +
                                  ": the rotor with its station held cannot stand in its " + plane +
                                  " plane (its stiffness is singular: a bearing is missing)");
    }
    Eigen::VectorXd k_ib(ni);
    for (int a = 0; a < ni; ++a) k_ib(a) = k(interior[a], station);
    return Eigen::VectorXd(-llt.solve(k_ib));
  };
  const Eigen::VectorXd psi_x = constraint_shape(k_x, k_x_ii, "x-z"), psi_y = constraint_shape(k_y, k_y_ii, "y-z");
  // Column 0, the constraint mode: the planes' mean static shape (each
  // plane's exact one for isotropic bearings), so that Guyan's reduction
  // favours neither plane.
  Eigen::MatrixXd planar = Eigen::MatrixXd::Zero(np, planar_modes);
  const Eigen::VectorXd psi_mean = 0.5 * (psi_x + psi_y);
  planar(station, 0) = 1.0;
  for (int a = 0; a < ni; ++a) planar(interior[a], 0) = psi_mean(a);
  // The interior shapes, each placed in both planes (so the mass stays
  // isotropic and the contact sees one station mass): the static correction
  // (psi_x - psi_y) / 2, which turns the mean static shape into either
  // plane's own (plus in x-z, minus in y-z), and the fixed-interface modes
  // of both planes, lowest frequency first (the correction at the lower of
  // its Rayleigh quotients in the two planes: it is needed as early as the
  // modes of its frequency; put first, it cost the seal example its first
  // mode at 2 planar modes, test_rotor_reduction,
  // FrequenciesAndResponsesConvergeWithModes). M-orthonormalised in that
  // order; a shape already in the span is left out, so isotropic bearings
  // (no correction, the planes' modes the same) give Craig-Bampton's basis.
  // With anisotropic bearings each plane's basis holds its own static shape
  // and modes, which the planes' mean did not
  // (AnisotropicBearingsConvergeToTheFullModel).
  struct Candidate {
    double omega2 = 0.0;  // its frequency squared [rad^2/s^2]: the order taken
    Eigen::VectorXd shape;
    double scale = 0.0;  // the M-norm it is judged new against
  };
  std::vector<Candidate> candidates;
  {
    // A correction below kNewShare of the mean static shape is the planes'
    // rounding, not a shape (judged against psi_mean, not against itself).
    const Eigen::VectorXd d = 0.5 * (psi_x - psi_y);
    const double m_norm2 = d.dot(m_ii * d);
    if (m_norm2 > 0.0) {
      const double omega2 = std::min(d.dot(k_x_ii * d), d.dot(k_y_ii * d)) / m_norm2;
      candidates.push_back({omega2, d, std::sqrt(std::max(0.0, psi_mean.dot(m_ii * psi_mean)))});
    }
  }
  if (planar_modes > 1) {
    for (const Eigen::MatrixXd* k_ii : {&k_x_ii, &k_y_ii}) {
      const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(*k_ii, m_ii);
      if (eig.info() != Eigen::Success)
        throw std::runtime_error("rub station: the fixed-interface modes did not converge");
      for (int k_mode = 0; k_mode < ni; ++k_mode) {
        candidates.push_back({eig.eigenvalues()(k_mode), eig.eigenvectors().col(k_mode), 1.0});
      }
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& a, const Candidate& b) { return a.omega2 < b.omega2; });
  // Gram-Schmidt in M_ii, twice (Kahan's "twice is enough"). A shape that
  // keeps less than kNewShare of its scale is in the span already: the two
  // planes' copies of one mode (isotropic bearings) differ by the
  // eigensolver's rounding, about 1e-12 of the mode, and any difference a
  // bearing makes is orders above 1e-8.
  constexpr double kNewShare = 1e-8;
  // Each kept shape u with M_ii u beside it: u . M_ii v = (M_ii u) . v.
  std::vector<Eigen::VectorXd> kept, m_kept;
  for (const Candidate& c : candidates) {
    if (static_cast<int>(kept.size()) == planar_modes - 1) break;
    Eigen::VectorXd v = c.shape;
    for (int pass = 0; pass < 2; ++pass) {
      for (std::size_t k = 0; k < kept.size(); ++k) v -= m_kept[k].dot(v) * kept[k];
    }
    const double after = std::sqrt(std::max(0.0, v.dot(m_ii * v)));
    if (!(after > kNewShare * c.scale)) continue;
    kept.push_back(v / after);
    m_kept.push_back(m_ii * kept.back());
  }
  if (static_cast<int>(kept.size()) != planar_modes - 1) {  // the modes of one plane alone span the interior
    throw std::runtime_error("rub station: the interior shapes do not span the rotor's planar DOFs");
  }
  for (int k_shape = 1; k_shape < planar_modes; ++k_shape) {
    for (int a = 0; a < ni; ++a) planar(interior[a], k_shape) = kept[k_shape - 1](a);
  }
  planar_ = std::move(planar);
}

ReducedRotor RotorReduction::reduce(int planar_modes) const {
  if (planar_modes < 1 || planar_modes > most_planar_modes()) {
    throw std::invalid_argument("retained modes: " + std::to_string(planar_modes) +
                                " is out of range; accepted: 1 to " + std::to_string(most_planar_modes()) +
                                " (the count this reduction was built for)");
  }
  const RotorMatrices& m = m_;
  const int np = static_cast<int>(planar_.rows());
  // Both planes: columns [x shape, y twin] per planar shape.
  const int n = static_cast<int>(m.M.rows()), size = 2 * planar_modes;
  Eigen::MatrixXd psi = Eigen::MatrixXd::Zero(n, size);
  for (int k = 0; k < planar_modes; ++k) {
    for (int a = 0; a < np; ++a) {
      psi(x_plane_[a], 2 * k) = planar_(a, k);
      psi(y_plane_[a], 2 * k + 1) = twin_sign_[a] * planar_(a, k);
    }
  }
  const Eigen::MatrixXd m_cb = psi.transpose() * m.M * psi;
  // q_cb = T q: eta = xi - M_ee^-1 M_eu u.
  Eigen::MatrixXd t = Eigen::MatrixXd::Identity(size, size);
  if (size > 2) {
    t.bottomLeftCorner(size - 2, 2) =
        -m_cb.bottomRightCorner(size - 2, size - 2).llt().solve(m_cb.bottomLeftCorner(size - 2, 2));
  }
  ReducedRotor r;
  r.station_node = station_node_;
  r.planar_modes = planar_modes;
  r.node_z_m = node_z_m_;
  r.support_nodes = m.support_nodes;
  r.expansion = psi * t;
  auto project = [&](const Eigen::MatrixXd& x) { return Eigen::MatrixXd(r.expansion.transpose() * x * r.expansion); };
  r.matrices.M = project(m.M);
  r.matrices.K = project(m.K);
  r.matrices.C = project(m.C);
  r.matrices.G = project(m.G);
  r.station_mass_kg = r.matrices.M(ReducedRotor::kStationX, ReducedRotor::kStationX);
  Eigen::VectorXd rigid_y = Eigen::VectorXd::Zero(m.M.rows());
  for (std::size_t a = 0; a < y_plane_.size(); ++a) rigid_y(y_plane_[a]) = twin_sign_[a] > 0.0 ? 1.0 : 0.0;  // every y
  r.unit_weight_kg = r.expansion.transpose() * (m.M * rigid_y);
  // The promised M = diag(m_st, m_st, I) holds when the two planes are twins
  // (an axisymmetric rotor in [x, y, alpha, beta] per node); matrices from
  // elsewhere (imported) may not be.
  Eigen::MatrixXd want = Eigen::MatrixXd::Identity(size, size);
  want(0, 0) = want(1, 1) = r.station_mass_kg;
  if (!((r.matrices.M - want).cwiseAbs().maxCoeff() <= 1e-9 * std::max(1.0, r.station_mass_kg))) {
    throw std::invalid_argument(
        "rub station: node " + std::to_string(station_node_) +
        ": the rotor's mass is not the same in its x-z and y-z planes (M's y, alpha rows are not the x, -beta rows: "
        "matrices in another DOF order, a point mass or a bearing's added mass that differs in x and y (mx != my, "
        "mxy != 0), or a rotor that is not axisymmetric)");
  }
  return r;
}

ReducedRotor reduce_rotor(const FeRotor& rotor, const RotorMatrices& m, int station_node, int planar_modes) {
  return RotorReduction(rotor, m, station_node, planar_modes).reduce(planar_modes);
}

std::vector<Mode> modes(const ReducedRotor& r, double speed_rad_per_s, int count) {
  return modes(r.matrices, speed_rad_per_s, count, r.expansion, r.support_nodes);
}

Eigen::MatrixXcd dynamic_stiffness(const RotorMatrices& m, double w) {
  const std::complex<double> i(0.0, 1.0);
  return m.K.cast<std::complex<double>>() - w * w * m.M.cast<std::complex<double>>() +
         i * w * (m.C + w * m.G).cast<std::complex<double>>();
}

Eigen::VectorXcd unbalance_forces(int dofs, const std::vector<RotorUnbalance>& unbalances, double w,
                                  int support_nodes) {
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(dofs);
  const int nodes = (dofs - 2 * support_nodes) / 4;
  for (const RotorUnbalance& u : unbalances) {
    if (u.node < 0 || u.node >= nodes) {
      throw std::invalid_argument("unbalance: node " + std::to_string(u.node) + " is out of range; accepted: 0 to " +
                                  std::to_string(nodes - 1));
    }
    const std::complex<double> force = u.me_kg_m * w * w * std::polar(1.0, u.phase_rad);
    f(dof_index(u.node, kDofX)) += force;
    f(dof_index(u.node, kDofY)) += std::complex<double>(0.0, -1.0) * force;
  }
  return f;
}

Eigen::VectorXcd unbalance_response(const RotorMatrices& m, const std::vector<RotorUnbalance>& unbalances,
                                    double w_rad_per_s) {
  return dynamic_stiffness(m, w_rad_per_s)
      .partialPivLu()
      .solve(unbalance_forces(static_cast<int>(m.M.rows()), unbalances, w_rad_per_s, m.support_nodes));
}

Eigen::VectorXcd unbalance_response(const ReducedRotor& r, const std::vector<RotorUnbalance>& unbalances,
                                    double w_rad_per_s) {
  const Eigen::MatrixXcd e = r.expansion.cast<std::complex<double>>();
  const Eigen::VectorXcd f =
      unbalance_forces(static_cast<int>(r.expansion.rows()), unbalances, w_rad_per_s, r.support_nodes);
  return e * dynamic_stiffness(r.matrices, w_rad_per_s).partialPivLu().solve(e.transpose() * f);
}

ResponseReference::ResponseReference(const FeRotor& rotor, const RotorMatrices& full,
                                     std::vector<RotorUnbalance> unbalances, std::vector<double> speeds_rad_per_s,
                                     std::vector<int> watched_nodes)
    : unbalances_(std::move(unbalances)), speeds_rad_per_s_(std::move(speeds_rad_per_s)) {
  for (const int node : watched_nodes) {
    if (node < 0 || node >= rotor.nodes()) {
      throw std::invalid_argument("probe node " + std::to_string(node) + " is out of range; accepted: 0 to " +
                                  std::to_string(rotor.nodes() - 1));
    }
    watched_dofs_.push_back(dof_index(node, kDofX));
    watched_dofs_.push_back(dof_index(node, kDofY));
  }
  if (unbalances_.empty()) speeds_rad_per_s_.clear();
  for (const double w : speeds_rad_per_s_) {
    full_.push_back(unbalance_response(full, unbalances_, w));
    double big = 0.0;
    for (int node = 0; node < rotor.nodes(); ++node) {
      big = std::max(
          {big, std::abs(full_.back()(dof_index(node, kDofX))), std::abs(full_.back()(dof_index(node, kDofY)))});
    }
    largest_m_.push_back(big);
  }
}

double ResponseReference::error(const ReducedRotor& r) const {
  double worst = 0.0;
  for (std::size_t s = 0; s < speeds_rad_per_s_.size(); ++s) {
    const Eigen::VectorXcd got = unbalance_response(r, unbalances_, speeds_rad_per_s_[s]);
    for (const int i : watched_dofs_) worst = std::max(worst, std::abs(got(i) - full_[s](i)) / largest_m_[s]);
  }
  return worst;
}

}  // namespace rotor_rub::core
