#include "rotor_rub_sim/core/fe_rotor.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <boost/math/tools/roots.hpp>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>

#include "rotor/for_each_index.hpp"
#include "rotor/modal_roots.hpp"

namespace rotor_rub::core {
namespace {

// An 8x8 matrix from its rows, written out as the textbooks print them.
ElementMatrix rows(std::initializer_list<std::initializer_list<double>> r) {
  ElementMatrix m;
  int i = 0;
  for (const auto& row : r) {
    int j = 0;
    for (const double v : row) m(i, j++) = v;
    ++i;
  }
  return m;
}

struct Section {
  double area_m2, second_moment_m4, phi, length_m;
};

// A = pi (od^2 - id^2) / 4, I = pi (od^4 - id^4) / 64, and the shear
// parameter phi = 12 E I / (kappa G A L^2).
Section section(const ShaftElement& e) {
  const double od = e.outer_diameter_m, id = e.inner_diameter_m, L = e.length_m;
  Section s;
  s.area_m2 = M_PI * (od * od - id * id) / 4.0;
  s.second_moment_m4 = M_PI * (od * od * od * od - id * id * id * id) / 64.0;
  const double kappa = cowper_shear_coefficient(e.material.poisson_ratio(), id / od);
  s.phi = 12.0 * e.material.youngs_modulus_Pa * s.second_moment_m4 /
          (kappa * e.material.shear_modulus_Pa * s.area_m2 * L * L);
  s.length_m = L;
  return s;
}

[[noreturn]] void refuse(const std::string& what) { throw std::invalid_argument(what); }

}  // namespace

DiskElement DiskElement::from_geometry(int node, const Material& material, double width_m, double inner_diameter_m,
                                       double outer_diameter_m) {
  DiskElement d;
  d.node = node;
  const double od2 = outer_diameter_m * outer_diameter_m, id2 = inner_diameter_m * inner_diameter_m;
  d.mass_kg = material.density_kg_per_m3 * M_PI * width_m * (od2 - id2) / 4.0;
  d.polar_inertia_kg_m2 = d.mass_kg * (od2 + id2) / 8.0;
  d.diametral_inertia_kg_m2 = d.polar_inertia_kg_m2 / 2.0 + d.mass_kg * width_m * width_m / 12.0;
  return d;
}

double cowper_shear_coefficient(double nu, double r) {
  const double a = (1.0 + r * r) * (1.0 + r * r);
  return 6.0 * a * (1.0 + nu) / (a * (7.0 + 6.0 * nu) + r * r * (20.0 + 12.0 * nu));
}

ElementMatrix shaft_mass(const ShaftElement& e) {
  const Section s = section(e);
  const double L = s.length_m, p = s.phi, L2 = L * L, q = (1.0 + p) * (1.0 + p);
  const double rho = e.material.density_kg_per_m3;
  // Translational inertia (Friswell et al. eq. 5.108, with shear).
  const double m1 = 468 + 882 * p + 420 * p * p, m2 = 66 + 115.5 * p + 52.5 * p * p, m3 = 162 + 378 * p + 210 * p * p,
               m4 = 39 + 94.5 * p + 52.5 * p * p, m5 = 12 + 21 * p + 10.5 * p * p, m7 = 9 + 21 * p + 10.5 * p * p;
  const ElementMatrix mt = rows({
      {m1, 0, 0, L * m2, m3, 0, 0, -L * m4},
      {0, m1, -L * m2, 0, 0, m3, L * m4, 0},
      {0, -L * m2, L2 * m5, 0, 0, -L * m4, -L2 * m7, 0},
      {L * m2, 0, 0, L2 * m5, L * m4, 0, 0, -L2 * m7},
      {m3, 0, 0, L * m4, m1, 0, 0, -L * m2},
      {0, m3, -L * m4, 0, 0, m1, L * m2, 0},
      {0, L * m4, -L2 * m7, 0, 0, L * m2, L2 * m5, 0},
      {-L * m4, 0, 0, -L2 * m7, -L * m2, 0, 0, L2 * m5},
  });
  // Rotary inertia of the cross-sections.
  const double r1 = 252, r2 = 21 - 105 * p, r4 = 28 + 35 * p + 70 * p * p, r5 = 7 + 35 * p - 35 * p * p;
  const ElementMatrix mr = rows({
      {r1, 0, 0, L * r2, -r1, 0, 0, L * r2},
      {0, r1, -L * r2, 0, 0, -r1, -L * r2, 0},
      {0, -L * r2, L2 * r4, 0, 0, L * r2, -L2 * r5, 0},
      {L * r2, 0, 0, L2 * r4, -L * r2, 0, 0, -L2 * r5},
      {-r1, 0, 0, -L * r2, r1, 0, 0, -L * r2},
      {0, -r1, L * r2, 0, 0, r1, L * r2, 0},
      {0, -L * r2, -L2 * r5, 0, 0, L * r2, L2 * r4, 0},
      {L * r2, 0, 0, -L2 * r5, -L * r2, 0, 0, L2 * r4},
  });
  return rho * s.area_m2 * L / (1260.0 * q) * mt + rho * s.second_moment_m4 / (210.0 * L * q) * mr;
}

ElementMatrix shaft_stiffness(const ShaftElement& e) {
  const Section s = section(e);
  const double L = s.length_m, a = 4.0 + s.phi, b = 2.0 - s.phi, L2 = L * L;
  const ElementMatrix k = rows({
      {12, 0, 0, 6 * L, -12, 0, 0, 6 * L},
      {0, 12, -6 * L, 0, 0, -12, -6 * L, 0},
      {0, -6 * L, a * L2, 0, 0, 6 * L, b * L2, 0},
      {6 * L, 0, 0, a * L2, -6 * L, 0, 0, b * L2},
      {-12, 0, 0, -6 * L, 12, 0, 0, -6 * L},
      {0, -12, 6 * L, 0, 0, 12, 6 * L, 0},
      {0, -6 * L, b * L2, 0, 0, 6 * L, a * L2, 0},
      {6 * L, 0, 0, b * L2, -6 * L, 0, 0, a * L2},
  });
  return e.material.youngs_modulus_Pa * s.second_moment_m4 / (L * L2 * (1.0 + s.phi)) * k;
}

ElementMatrix shaft_gyroscopic(const ShaftElement& e) {
  const Section s = section(e);
  const double L = s.length_m, p = s.phi, L2 = L * L, q = (1.0 + p) * (1.0 + p);
  const double g1 = 252, g2 = 21 - 105 * p, g4 = 28 + 35 * p + 70 * p * p, g5 = 7 + 35 * p - 35 * p * p;
  const ElementMatrix g = rows({
      {0, g1, -L * g2, 0, 0, -g1, -L * g2, 0},
      {-g1, 0, 0, -L * g2, g1, 0, 0, -L * g2},
      {L * g2, 0, 0, L2 * g4, -L * g2, 0, 0, -L2 * g5},
      {0, L * g2, -L2 * g4, 0, 0, -L * g2, L2 * g5, 0},
      {0, -g1, L * g2, 0, 0, g1, L * g2, 0},
      {g1, 0, 0, L * g2, -g1, 0, 0, L * g2},
      {L * g2, 0, 0, -L2 * g5, -L * g2, 0, 0, L2 * g4},
      {0, L * g2, L2 * g5, 0, 0, -L * g2, -L2 * g4, 0},
  });
  return e.material.density_kg_per_m3 * s.second_moment_m4 / (105.0 * L * q) * g;
}

namespace {

// C += M Phi diag(2 zeta_i w_i) Phi^T M over the undamped modes of
// (M, K_sym), Phi M-normalised: each such mode alone gets its zeta_i (where
// the rest of C is nil and at rest: test_fe_rotor,
// ModalDampingGivesEveryModeItsRatio, ModalDampingRatiosGoByNaturalFrequency,
// ALossFactorDampsTheShaftsShareOfEachMode). Modes below 1 rpm (rigid-body
// ones) are left undamped, as ROSS does. shaft_k: the shaft elements'
// stiffness (null for imported matrices), for the loss factor. Where K's
// symmetric part has a negative eigenvalue (strongly cross-coupled
// bearings), its modes are not the rotor's and a mode's share of strain
// energy is no share: refused (ModalDampingRefusesAnIndefiniteStiffness).
void add_modal_damping(const FeRotor& rotor, const Eigen::MatrixXd* shaft_k, RotorMatrices& m) {
  const std::vector<double>& ratios = rotor.modal_damping_ratios;
  const double eta = rotor.shaft_loss_factor;
  if (ratios.empty() && eta == 0.0) return;
  if (ratios.empty() && rotor.modal_damping_higher_ratio) {
    refuse("rotor: modal_damping: higher_ratio without ratios; accepted: beside ratios");
  }
  if (eta != 0.0 && !ratios.empty()) refuse("rotor: modal_damping gives both ratios and a loss factor; accepted: one");
  if (eta != 0.0 && !shaft_k)
    refuse("rotor: modal_damping: loss_factor needs shaft elements; accepted: ratio or ratios");
  const Eigen::MatrixXd k_sym = 0.5 * (m.K + m.K.transpose());
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(k_sym, m.M);
  if (eig.info() != Eigen::Success) refuse("rotor: modal_damping: the undamped modes did not converge");
  constexpr double kOneRpm2 = modal::kRigidBodyBelow_rad_per_s * modal::kRigidBodyBelow_rad_per_s;
  const Eigen::VectorXd& w2s = eig.eigenvalues();
  // The solver's error in w^2: eps times the stiffest mode's (a rigid-body
  // mode's 0 comes out as that, of either sign).
  const double rounding = 64.0 * std::numeric_limits<double>::epsilon() * std::abs(w2s(w2s.size() - 1));
  if (w2s(0) < -(kOneRpm2 + rounding)) {
    refuse("rotor: modal_damping: K's symmetric part has the eigenvalue " + std::to_string(w2s(0)) +
           " (per unit modal mass; cross-coupled bearings): its modes are not the rotor's; accepted: a K whose "
           "symmetric part is positive semi-definite, or shaft_damping");
  }
  // Two roots within this of each other are one natural frequency, twice:
  // an isotropic rotor's planes, which the solver parts by its rounding
  // (3e-9 of the lowest w^2 on bearings of 1e14 N/m), or 1e-6 relative.
  constexpr double kSameFrequency = 1e-6;
  Eigen::VectorXd two_zeta_w = Eigen::VectorXd::Zero(w2s.size());
  std::size_t frequency = 0;  // the natural frequency's index, a double one once
  double last_w2 = 0.0;
  for (Eigen::Index i = 0; i < two_zeta_w.size(); ++i) {
    const double w2 = w2s(i);
    if (!(w2 > kOneRpm2)) continue;
    if (last_w2 > 0.0 && w2 - last_w2 > kSameFrequency * w2 + rounding) ++frequency;
    last_w2 = w2;
    if (eta != 0.0) {
      // The shaft's share as a ratio of two quadratic forms of the same
      // vector: the solver's error in it (stiff modes' content on stiff
      // bearings) enters both, where beside w^2 it would not cancel.
      const Eigen::VectorXd phi = eig.eigenvectors().col(i);
      const double share = phi.dot(*shaft_k * phi) / phi.dot(k_sym * phi);
      // Above 1 the bearings' energy is negative; rounding on penalty-stiff
      // bearings (1e14 N/m) reaches 6e-5 (ALossFactorDampsTheShaftsShareOfEachMode).
      if (!(share <= 1.0 + 1e-3)) {
        refuse("rotor: modal_damping: loss_factor: the mode of " + std::to_string(std::sqrt(w2)) +
               " rad/s has a shaft share of its strain energy of " + std::to_string(share) +
               " (bearings whose symmetric stiffness is indefinite); accepted: ratio or ratios");
      }
      two_zeta_w(i) = eta * std::sqrt(w2) * share;
    } else {
      const double ratio =
          frequency < ratios.size() ? ratios[frequency] : rotor.modal_damping_higher_ratio.value_or(ratios.back());
      two_zeta_w(i) = 2.0 * ratio * std::sqrt(w2);
    }
  }
  const Eigen::MatrixXd m_phi = m.M * eig.eigenvectors();
  m.C += m_phi * two_zeta_w.asDiagonal() * m_phi.transpose();
}

// Support nodes are numbered on from the shaft's last, each with one point
// mass of positive mx and my (its whole mass: a DOF without one would have
// none), in turn: nodes(), nodes() + 1, ... (ROSS's order of their DOFs).
void check_supports(const FeRotor& rotor) {
  std::vector<int> support_masses(static_cast<std::size_t>(rotor.support_nodes()), 0);
  for (std::size_t i = 0; i < rotor.point_masses.size(); ++i) {
    const PointMass& p = rotor.point_masses[i];
    const int k = p.node - rotor.nodes();
    if (k < 0) continue;
    const std::string item = "point mass " + std::to_string(i);
    if (k >= rotor.support_nodes() || ++support_masses[static_cast<std::size_t>(k)] > 1) {
      refuse(item + ": node " + std::to_string(p.node) + " is out of range; accepted: 0 to " +
             std::to_string(rotor.nodes() - 1) + " (a shaft node) or the next support node, " +
             std::to_string(rotor.nodes()) + " on, one point mass each");
    }
    if (!(p.mx_kg > 0.0 && p.my_kg > 0.0)) {
      refuse(item + ": support node " + std::to_string(p.node) + " has mx_kg " + std::to_string(p.mx_kg) + ", my_kg " +
             std::to_string(p.my_kg) + "; accepted: both > 0 (its whole mass)");
    }
  }
}

}  // namespace

RotorMatrices assemble(const FeRotor& rotor) {
  if (rotor.imported) {
    if (rotor.imported->M.rows() != rotor.dofs() || !rotor.shaft.empty() || !rotor.disks.empty() ||
        !rotor.bearings.empty() || !rotor.point_masses.empty()) {
      refuse("rotor: imported matrices of " + std::to_string(rotor.imported->M.rows()) + " DOF for " +
             std::to_string(rotor.nodes()) + " nodes and " + std::to_string(rotor.support_nodes()) +
             " support nodes, or beside elements; accepted: 4 DOF per node and 2 per support node, alone");
    }
    RotorMatrices m = *rotor.imported;
    add_modal_damping(rotor, nullptr, m);
    return m;
  }
  if (rotor.shaft.empty()) refuse("rotor: no shaft elements");
  const int n = rotor.dofs();
  RotorMatrices m;
  m.M = m.K = m.C = m.G = Eigen::MatrixXd::Zero(n, n);
  m.support_nodes = rotor.support_nodes();
  for (std::size_t i = 0; i < rotor.shaft.size(); ++i) {
    const ShaftElement& e = rotor.shaft[i];
    const std::string item = "shaft element " + std::to_string(i);
    if (!(e.length_m > 0.0))
      refuse(item + ": length_m " + std::to_string(e.length_m) + " is out of range; accepted: (0, inf)");
    if (!(e.outer_diameter_m > 0.0)) {
      refuse(item + ": outer_diameter_m " + std::to_string(e.outer_diameter_m) +
             " is out of range; accepted: (0, inf)");
    }
    if (!(e.inner_diameter_m >= 0.0 && e.inner_diameter_m < e.outer_diameter_m)) {
      refuse(item + ": inner_diameter_m " + std::to_string(e.inner_diameter_m) +
             " is out of range; accepted: [0, outer_diameter_m)");
    }
    const int at = 4 * static_cast<int>(i);
    const ElementMatrix mass = shaft_mass(e), stiffness = shaft_stiffness(e);
    m.M.block<8, 8>(at, at) += mass;
    m.K.block<8, 8>(at, at) += stiffness;
    m.C.block<8, 8>(at, at) +=
        e.damping.mass_proportional_per_s * mass + e.damping.stiffness_proportional_s * stiffness;
    m.G.block<8, 8>(at, at) += shaft_gyroscopic(e);
  }
  const Eigen::MatrixXd shaft_k = rotor.shaft_loss_factor != 0.0 ? m.K : Eigen::MatrixXd();
  auto check_node = [&](int node, const std::string& item) {
    if (node < 0 || node >= rotor.nodes()) {
      refuse(item + ": node " + std::to_string(node) + " is out of range; accepted: 0 to " +
             std::to_string(rotor.nodes() - 1) + " (" + std::to_string(rotor.shaft.size()) + " shaft elements)");
    }
  };
  for (std::size_t i = 0; i < rotor.disks.size(); ++i) {
    const DiskElement& d = rotor.disks[i];
    check_node(d.node, "disk " + std::to_string(i));
    const int x = dof_index(d.node, kDofX), y = dof_index(d.node, kDofY), a = dof_index(d.node, kDofAlpha),
              b = dof_index(d.node, kDofBeta);
    m.M(x, x) += d.mass_kg;
    m.M(y, y) += d.mass_kg;
    m.M(a, a) += d.diametral_inertia_kg_m2;
    m.M(b, b) += d.diametral_inertia_kg_m2;
    m.G(a, b) += d.polar_inertia_kg_m2;
    m.G(b, a) -= d.polar_inertia_kg_m2;
  }
  check_supports(rotor);
  const int all_nodes = rotor.nodes() + rotor.support_nodes();
  auto check_any_node = [&](int node, const std::string& item, const char* key) {
    if (node < 0 || node >= all_nodes) {
      refuse(item + ": " + key + " " + std::to_string(node) + " is out of range; accepted: 0 to " +
             std::to_string(all_nodes - 1) + " (" + std::to_string(rotor.nodes()) + " shaft nodes, " +
             std::to_string(rotor.support_nodes()) + " support nodes)");
    }
  };
  for (std::size_t i = 0; i < rotor.point_masses.size(); ++i) {
    const PointMass& p = rotor.point_masses[i];
    check_any_node(p.node, "point mass " + std::to_string(i), "node");
    if (!(p.mx_kg >= 0.0 && p.my_kg >= 0.0 && std::isfinite(p.mx_kg) && std::isfinite(p.my_kg))) {
      refuse("point mass " + std::to_string(i) + ": mx_kg " + std::to_string(p.mx_kg) + ", my_kg " +
             std::to_string(p.my_kg) + "; accepted: [0, inf)");
    }
    m.M(rotor.translation_dof(p.node, kDofX), rotor.translation_dof(p.node, kDofX)) += p.mx_kg;
    m.M(rotor.translation_dof(p.node, kDofY), rotor.translation_dof(p.node, kDofY)) += p.my_kg;
  }
  for (std::size_t i = 0; i < rotor.bearings.size(); ++i) {
    const BearingElement& b = rotor.bearings[i];
    const std::string item = "bearing " + std::to_string(i);
    check_any_node(b.node, item, "node");
    if (b.link_node != -1) check_any_node(b.link_node, item, "link_node");
    if (b.link_node == b.node) refuse(item + ": link_node " + std::to_string(b.node) + " is its own node");
    if (!(b.mxy == b.myx && b.mxx >= 0.0 && b.myy >= 0.0 && b.mxy * b.mxy <= b.mxx * b.myy)) {
      refuse(item + ": added mass mxx " + std::to_string(b.mxx) + ", mxy " + std::to_string(b.mxy) + ", myx " +
             std::to_string(b.myx) + ", myy " + std::to_string(b.myy) +
             "; accepted: mxy == myx and mxy^2 <= mxx myy (symmetric, positive semi-definite)");
    }
    // Each 2 x 2 block on the node, and with a link, on the link and
    // against it: the force is -k (u_node - u_link).
    const Eigen::Matrix2d k{{b.kxx, b.kxy}, {b.kyx, b.kyy}}, c{{b.cxx, b.cxy}, {b.cyx, b.cyy}},
        mass{{b.mxx, b.mxy}, {b.myx, b.myy}};
    auto add = [&](int row_node, int col_node, double sign) {
      for (int i_xy = 0; i_xy < 2; ++i_xy) {
        for (int j_xy = 0; j_xy < 2; ++j_xy) {
          const int row = rotor.translation_dof(row_node, i_xy), col = rotor.translation_dof(col_node, j_xy);
          m.K(row, col) += sign * k(i_xy, j_xy);
          m.C(row, col) += sign * c(i_xy, j_xy);
          m.M(row, col) += sign * mass(i_xy, j_xy);
        }
      }
    };
    add(b.node, b.node, 1.0);
    if (b.link_node != -1) {
      add(b.link_node, b.link_node, 1.0);
      add(b.node, b.link_node, -1.0);
      add(b.link_node, b.node, -1.0);
    }
  }
  add_modal_damping(rotor, &shaft_k, m);
  return m;
}

const char* to_string(ModeWhirl w) {
  switch (w) {
    case ModeWhirl::kForward:
      return "forward";
    case ModeWhirl::kBackward:
      return "backward";
    case ModeWhirl::kMixed:
      return "mixed";
  }
  throw std::logic_error("to_string: not a ModeWhirl");
}

namespace {

// A node's orbit x = Re(u e^{i w t}), y = Re(v e^{i w t}) turns forward
// (counter-clockwise) when Im(conj(u) v) < 0 (u = 1, v = -i: x = cos, y = sin).
// Relative to the orbit's size; below 1e-3 it is a line (a planar mode).
// The slopes (dx/dz, dy/dz) = (beta, -alpha) whirl the same way as the
// displacements and are judged alike, so that a mode with (nearly) no
// displacement, a disk's pure tilt, gets the whirl of its tilt; a kind of
// motion (displacements, slopes) below 1e-6 of the shape's largest entry is
// left out as roundoff.
ModeWhirl whirl_of(const Eigen::VectorXcd& shape, int supports) {
  using Complex = std::complex<double>;
  const int nodes = (static_cast<int>(shape.size()) - 2 * supports) / 4;
  struct Pair {
    int u, v;  // the DOFs of an orbit's x and its y (times v_sign)
  };
  // The displacements (shaft and support nodes), then the slopes.
  std::vector<Pair> kinds[2];
  for (int k = 0; k < nodes; ++k) {
    kinds[0].push_back({dof_index(k, kDofX), dof_index(k, kDofY)});
    kinds[1].push_back({dof_index(k, kDofBeta), dof_index(k, kDofAlpha)});
  }
  for (int j = 0; j < supports; ++j) kinds[0].push_back({4 * nodes + 2 * j, 4 * nodes + 2 * j + 1});
  const double v_sign[2] = {1.0, -1.0};
  const double entry = shape.cwiseAbs().maxCoeff();
  bool forward = false, backward = false;
  for (int kind = 0; kind < 2; ++kind) {
    double largest = 0.0;
    for (const Pair& p : kinds[kind]) largest = std::max(largest, std::norm(shape(p.u)) + std::norm(shape(p.v)));
    if (!(std::sqrt(largest) > 1e-6 * entry)) continue;
    for (const Pair& p : kinds[kind]) {
      const Complex u = shape(p.u), v = v_sign[kind] * shape(p.v);
      const double size = std::norm(u) + std::norm(v);
      if (size < 1e-12 * largest) continue;  // a node at rest (a bearing's, say)
      const double turn = -std::imag(std::conj(u) * v) / size;
      if (turn > 1e-3) forward = true;
      if (turn < -1e-3) backward = true;
    }
  }
  if (forward && backward) return ModeWhirl::kMixed;
  return backward ? ModeWhirl::kBackward : ModeWhirl::kForward;  // a planar mode counts as forward
}

}  // namespace

Eigen::VectorXcd eigenvalues(const RotorMatrices& m, double speed_rad_per_s) {
  Eigen::MatrixXd l;
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(modal::first_order_matrix(m, speed_rad_per_s, l), false);
  if (eig.info() != Eigen::Success) throw std::runtime_error("eigenvalues: the eigenvalue solver did not converge");
  return eig.eigenvalues();
}

// The lowest modes by shift-invert Arnoldi where it is certified complete
// (a large rotor's: a few tens of its roots in place of all), else every
// root by the QR, each refined (modal_roots.hpp).
std::vector<Mode> modes(const RotorMatrices& m, double speed_rad_per_s, int count, const Eigen::MatrixXd& expansion,
                        int expanded_support_nodes) {
  const int supports = expansion.size() > 0 ? expanded_support_nodes : m.support_nodes;
  using Complex = std::complex<double>;
  Eigen::MatrixXd l;
  const Eigen::MatrixXd a = modal::first_order_matrix(m, speed_rad_per_s, l);
  std::optional<std::vector<modal::ModeRoot>> roots = modal::lowest_mode_roots(a, l, count);
  if (!roots) roots = modal::refined_mode_roots(m, speed_rad_per_s, a, count);
  std::vector<Mode> out;
  for (const modal::ModeRoot& root : *roots) {
    const Complex lambda = root.lambda;
    Mode md;
    md.natural_frequency_rad_per_s = std::abs(lambda);
    md.damped_frequency_rad_per_s = lambda.imag();
    md.damping_ratio = -lambda.real() / std::abs(lambda);
    md.shape = expansion.size() > 0 ? Eigen::VectorXcd(expansion.cast<Complex>() * root.shape) : root.shape;
    Eigen::Index big = 0;
    md.shape.cwiseAbs().maxCoeff(&big);
    md.shape /= md.shape(big);
    md.whirl = whirl_of(md.shape, supports);
    out.push_back(std::move(md));
  }
  return out;
}

std::vector<std::vector<Mode>> campbell(const RotorMatrices& m, const std::vector<double>& speeds_rad_per_s, int count,
                                        unsigned jobs) {
  std::vector<std::vector<Mode>> out(speeds_rad_per_s.size());
  for_each_index(static_cast<int>(out.size()), jobs, [&](int s) {
    out[static_cast<std::size_t>(s)] = modes(m, speeds_rad_per_s[static_cast<std::size_t>(s)], count);
  });
  return out;
}

NonModeRoots non_mode_roots(const RotorMatrices& m, double speed_rad_per_s) {
  NonModeRoots out;
  for (const std::complex<double>& lambda : eigenvalues(m, speed_rad_per_s)) {
    if (!(std::abs(lambda) > modal::kRigidBodyBelow_rad_per_s)) {
      ++out.rigid_body;  // every one: how the QR splits a multiple zero into pairs does not count
      continue;
    }
    if (modal::oscillatory(lambda) || lambda.imag() < 0.0) continue;
    if (lambda.real() < 0.0) ++out.overdamped;
    if (lambda.real() > 0.0) ++out.diverging;
  }
  return out;
}

std::vector<CriticalSpeed> critical_speeds(const RotorMatrices& m, int count, double max_speed_rad_per_s, int samples,
                                           unsigned jobs) {
  if (samples < 1) throw std::invalid_argument("critical_speeds: samples " + std::to_string(samples) + " is below 1");
  using Roots = std::vector<std::complex<double>>;
  std::vector<CriticalSpeed> out;
  Eigen::MatrixXd l;
  // The modes that can cross in the range, and some way above (a mode that
  // crosses the cap changes the list's length: the search halves there).
  const double cap_rad_per_s = 1.5 * max_speed_rad_per_s + 1.0;
  auto roots_at = [&](double w) {
    const Eigen::MatrixXd a = modal::first_order_matrix(m, w, l);
    return modal::mode_roots_below(a, l, cap_rad_per_s);
  };
  using Complex = std::complex<double>;
  const Eigen::MatrixXcd mass = m.M.cast<Complex>(), stiffness = m.K.cast<Complex>(), gyro = m.G.cast<Complex>(),
                         damping = m.C.cast<Complex>();
  // Mode k's w_d - w between speeds a and b where the modes are as many at
  // both ends: a sign change is a crossing, located, polished and confirmed.
  // Its values from the eigenvalues alone: their error, eps times the
  // largest, moves a crossing by far less than the root finder's tolerance.
  auto locate = [&](int k, double a, double fa, double b, double fb) {
    std::uintmax_t iterations = 100;
    auto f = [&](double w) {
      const Roots roots = roots_at(w);
      return k < static_cast<int>(roots.size()) ? roots[static_cast<std::size_t>(k)].imag() - w
                                                : fb;  // a gap inside: the root lies before it
    };
    const auto r = boost::math::tools::toms748_solve(f, a, b, fa, fb, boost::math::tools::eps_tolerance<double>(20),
                                                     iterations);  // Newton polishes
    // Polished by Newton on Im lambda_k(w) - w with the refined root and,
    // from y^H Q(lambda, w) x = 0 with Q = lambda^2 M + lambda (C + w G) + K,
    // dlambda/dw = -y^H (lambda G) x / y^H (2 lambda M + C + w G) x: the
    // QR's eigenvalues carry an error of eps times the largest (about 1e-7
    // of a rig's lowest modes), which the refined root has not.
    double w = 0.5 * (r.first + r.second);
    const Roots there = roots_at(w);
    if (k >= static_cast<int>(there.size())) return;
    Complex lambda = there[static_cast<std::size_t>(k)];
    for (int step = 0; step < 3; ++step) {
      const Eigen::MatrixXcd d = damping + w * gyro;
      modal::QepVectors v;
      lambda = modal::refined_qep_root(mass, d, stiffness, lambda, {}, v);
      if (!v.refined) break;  // no Newton step on a root it could not refine: the bracket's w stays
      const Complex dlambda_dw =
          -v.left.dot(lambda * (gyro * v.right)) / v.left.dot((2.0 * lambda * mass + d) * v.right);
      const double slope = dlambda_dw.imag() - 1.0;
      const double next = w - (lambda.imag() - w) / slope;
      if (!std::isfinite(next) || !(next >= a && next <= b)) break;
      lambda += (next - w) * dlambda_dw;  // the next step's shift
      w = next;
    }
    // The refined modes there confirm the crossing: a real root the QR
    // left with an imaginary part above the filter's (its error grows
    // with the largest eigenvalue: stiff bearings) would shift the
    // indices and cross where no mode does.
    const std::vector<Mode> at = modes(m, w, k + 1);
    if (k < static_cast<int>(at.size()) &&
        std::abs(at[static_cast<std::size_t>(k)].damped_frequency_rad_per_s - w) <= 1e-9 * std::max(w, 1.0)) {
      out.push_back({k, w, at[static_cast<std::size_t>(k)].whirl, at[static_cast<std::size_t>(k)].damping_ratio});
    }
  };
  // Where the number of modes differs at the two ends (an overdamped pair the
  // spin turns into a mode enters the list below the others and shifts their
  // indices), the interval is halved down to where it changes, and each part
  // with as many modes at both ends is searched by index
  // (FeRotor.AModeEnteringBelowHidesNoCriticalSpeed).
  // Down to 1e-7 of the range: a crossing closer than that to a change is
  // not looked for.
  const double split_below = 1e-7 * max_speed_rad_per_s;
  std::function<void(double, const Roots&, double, const Roots&)> search = [&](double a, const Roots& ra, double b,
                                                                               const Roots& rb) {
    if (ra.size() != rb.size()) {
      if (!(b - a > split_below)) return;  // the change itself
      const double mid = 0.5 * (a + b);
      const Roots rm = roots_at(mid);
      search(a, ra, mid, rm);
      search(mid, rm, b, rb);
      return;
    }
    for (int k = 0; k < std::min(count, static_cast<int>(ra.size())); ++k) {
      const double fa = ra[static_cast<std::size_t>(k)].imag() - a, fb = rb[static_cast<std::size_t>(k)].imag() - b;
      if ((fa > 0.0) != (fb > 0.0)) locate(k, a, fa, b, fb);
    }
  };
  std::vector<Roots> grid(static_cast<std::size_t>(samples) + 1);
  for_each_index(samples + 1, jobs, [&](int s) {
    Eigen::MatrixXd own_l;  // each thread its own factor
    const Eigen::MatrixXd a = modal::first_order_matrix(m, max_speed_rad_per_s * s / samples, own_l);
    grid[static_cast<std::size_t>(s)] = modal::mode_roots_below(a, own_l, cap_rad_per_s);
  });
  for (int s = 1; s <= samples; ++s) {
    search(max_speed_rad_per_s * (s - 1) / samples, grid[static_cast<std::size_t>(s) - 1],
           max_speed_rad_per_s * s / samples, grid[static_cast<std::size_t>(s)]);
  }
  std::sort(out.begin(), out.end(),
            [](const CriticalSpeed& a, const CriticalSpeed& b) { return a.speed_rad_per_s < b.speed_rad_per_s; });
  return out;
}

}  // namespace rotor_rub::core
