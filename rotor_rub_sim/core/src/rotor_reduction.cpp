#include "rotor_rub_sim/core/rotor_reduction.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <complex>
#include <stdexcept>
#include <string>
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

Planes planes_of(int nodes) {
  Planes p;
  for (int node = 0; node < nodes; ++node) {
    p.x_plane.push_back(dof_index(node, kDofX));
    p.y_plane.push_back(dof_index(node, kDofY));
    p.twin_sign.push_back(1.0);
    p.x_plane.push_back(dof_index(node, kDofBeta));
    p.y_plane.push_back(dof_index(node, kDofAlpha));
    p.twin_sign.push_back(-1.0);
  }
  return p;
}

}  // namespace

ReducedRotor reduce_rotor(const FeRotor& rotor, const RotorMatrices& m, int station_node, int planar_modes) {
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
  const Planes planes = planes_of(nodes);
  const int np = static_cast<int>(planes.x_plane.size());
  // The x-z plane's stiffness of the basis: the shaft's (isotropic) with the
  // bearings' kxx and kyy averaged, symmetric. In planar indices.
  Eigen::MatrixXd k_plane(np, np), m_plane(np, np);
  for (int a = 0; a < np; ++a) {
    for (int b = 0; b < np; ++b) {
      const int xa = planes.x_plane[a], xb = planes.x_plane[b], ya = planes.y_plane[a], yb = planes.y_plane[b];
      const double sign = planes.twin_sign[a] * planes.twin_sign[b];
      k_plane(a, b) = 0.5 * (m.K(xa, xb) + sign * m.K(ya, yb));
      m_plane(a, b) = 0.5 * (m.M(xa, xb) + sign * m.M(ya, yb));
    }
  }
  k_plane = 0.5 * (k_plane + k_plane.transpose()).eval();
  // The station's x is planar index 2 * station_node; the interior is the rest.
  const int station = 2 * station_node;
  std::vector<int> interior;
  for (int a = 0; a < np; ++a) {
    if (a != station) interior.push_back(a);
  }
  const int ni = np - 1;
  Eigen::MatrixXd k_ii(ni, ni), m_ii(ni, ni);
  Eigen::VectorXd k_ib(ni);
  for (int a = 0; a < ni; ++a) {
    k_ib(a) = k_plane(interior[a], station);
    for (int b = 0; b < ni; ++b) {
      k_ii(a, b) = k_plane(interior[a], interior[b]);
      m_ii(a, b) = m_plane(interior[a], interior[b]);
    }
  }
  const Eigen::LLT<Eigen::MatrixXd> k_ii_llt(k_ii);
  // A pivot at roundoff is as singular as a negative one.
  if (k_ii_llt.info() != Eigen::Success || !(k_ii_llt.rcond() > 1e-14)) {
    throw std::invalid_argument("rub station: node " + std::to_string(station_node) +
                                ": the rotor with its station held cannot stand (its stiffness is singular: a "
                                "bearing is missing)");
  }
  // Planar basis: the constraint mode, then the fixed-interface modes.
  Eigen::MatrixXd planar = Eigen::MatrixXd::Zero(np, planar_modes);
  {
    const Eigen::VectorXd psi = -k_ii_llt.solve(k_ib);
    planar(station, 0) = 1.0;
    for (int a = 0; a < ni; ++a) planar(interior[a], 0) = psi(a);
  }
  if (planar_modes > 1) {
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k_ii, m_ii);
    if (eig.info() != Eigen::Success)
      throw std::runtime_error("rub station: the fixed-interface modes did not converge");
    for (int k = 1; k < planar_modes; ++k) {  // ascending; mass-normalised
      for (int a = 0; a < ni; ++a) planar(interior[a], k) = eig.eigenvectors()(a, k - 1);
    }
  }
  // Both planes: columns [x shape, y twin] per planar shape.
  const int n = static_cast<int>(m.M.rows()), size = 2 * planar_modes;
  Eigen::MatrixXd psi = Eigen::MatrixXd::Zero(n, size);
  for (int k = 0; k < planar_modes; ++k) {
    for (int a = 0; a < np; ++a) {
      psi(planes.x_plane[a], 2 * k) = planar(a, k);
      psi(planes.y_plane[a], 2 * k + 1) = planes.twin_sign[a] * planar(a, k);
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
  r.station_node = station_node;
  r.planar_modes = planar_modes;
  for (int node = 0; node < nodes; ++node) r.node_z_m.push_back(rotor.node_z_m(node));
  r.expansion = psi * t;
  auto project = [&](const Eigen::MatrixXd& x) { return Eigen::MatrixXd(r.expansion.transpose() * x * r.expansion); };
  r.matrices.M = project(m.M);
  r.matrices.K = project(m.K);
  r.matrices.C = project(m.C);
  r.matrices.G = project(m.G);
  r.station_mass_kg = r.matrices.M(ReducedRotor::kStationX, ReducedRotor::kStationX);
  Eigen::VectorXd rigid_y = Eigen::VectorXd::Zero(m.M.rows());
  for (int node = 0; node < nodes; ++node) rigid_y(dof_index(node, kDofY)) = 1.0;
  r.unit_weight_kg = r.expansion.transpose() * (m.M * rigid_y);
  // The promised M = diag(m_st, m_st, I) holds when the two planes are twins
  // (an axisymmetric rotor in [x, y, alpha, beta] per node); matrices from
  // elsewhere (imported) may not be.
  Eigen::MatrixXd want = Eigen::MatrixXd::Identity(size, size);
  want(0, 0) = want(1, 1) = r.station_mass_kg;
  if (!((r.matrices.M - want).cwiseAbs().maxCoeff() <= 1e-9 * std::max(1.0, r.station_mass_kg))) {
    throw std::invalid_argument(
        "rub station: node " + std::to_string(station_node) +
        ": the rotor's mass is not the same in its x-z and y-z planes (M's y, alpha rows are not the x, -beta rows: "
        "matrices in another DOF order, or of a rotor that is not axisymmetric)");
  }
  return r;
}

std::vector<Mode> modes(const ReducedRotor& r, double speed_rad_per_s, int count) {
  return modes(r.matrices, speed_rad_per_s, count, r.expansion);
}

Eigen::MatrixXcd dynamic_stiffness(const RotorMatrices& m, double w) {
  const std::complex<double> i(0.0, 1.0);
  return m.K.cast<std::complex<double>>() - w * w * m.M.cast<std::complex<double>>() +
         i * w * (m.C + w * m.G).cast<std::complex<double>>();
}

Eigen::VectorXcd unbalance_forces(int dofs, const std::vector<RotorUnbalance>& unbalances, double w) {
  Eigen::VectorXcd f = Eigen::VectorXcd::Zero(dofs);
  for (const RotorUnbalance& u : unbalances) {
    if (u.node < 0 || 4 * u.node >= dofs) {
      throw std::invalid_argument("unbalance: node " + std::to_string(u.node) + " is out of range; accepted: 0 to " +
                                  std::to_string(dofs / 4 - 1));
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
      .solve(unbalance_forces(static_cast<int>(m.M.rows()), unbalances, w_rad_per_s));
}

Eigen::VectorXcd unbalance_response(const ReducedRotor& r, const std::vector<RotorUnbalance>& unbalances,
                                    double w_rad_per_s) {
  const Eigen::MatrixXcd e = r.expansion.cast<std::complex<double>>();
  const Eigen::VectorXcd f = unbalance_forces(static_cast<int>(r.expansion.rows()), unbalances, w_rad_per_s);
  return e * dynamic_stiffness(r.matrices, w_rad_per_s).partialPivLu().solve(e.transpose() * f);
}

}  // namespace rotor_rub::core
