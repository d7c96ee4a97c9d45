/// @file
/// A flexible rotor as finite elements: the model and its modal analysis
/// (rotor_reduction.hpp reduces it to its rub station and a few modes, which
/// the contact methods run: flexible_rotor_model.hpp).
///
/// Coordinates: z along the shaft, 4 DOF per node, in the order
/// q = [x, y, alpha, beta] (alpha a rotation about x, beta about y; beta goes
/// with x as +dx/dz, alpha with y as -dy/dz: Friswell et al., "Dynamics of
/// Rotating Machines", 2010, ch. 5, the convention ROSS uses too). Node i sits
/// at the left end of shaft element i; element i joins nodes i and i + 1.
///
/// Equations of motion at a constant speed Omega [rad/s]:
///   M q'' + (C + Omega G) q' + K q = f,
/// G skew-symmetric (a disk's G[alpha, beta] = +I_p: forward whirl stiffens).
/// Shaft elements are Timoshenko beams: shear deformation (phi, with Cowper's
/// shear coefficient of a hollow circular section), rotary inertia and the
/// gyroscopic matrix; disks are rigid (mass, polar and diametral inertia);
/// bearings and seals are linear springs and dampers at a node's x and y,
/// constant here. A speed-dependent bearing would enter as K(Omega), C(Omega)
/// evaluated at each speed of a Campbell diagram (and, in a run, at each
/// step's speed); not in this version.
#pragma once

#include <Eigen/Dense>
#include <complex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace rotor_rub::core {

struct Material {
  double youngs_modulus_Pa = 211e9;  ///< E (steel)
  double shear_modulus_Pa = 81.2e9;  ///< G
  double density_kg_per_m3 = 7810.0;
  double poisson_ratio() const { return youngs_modulus_Pa / (2.0 * shear_modulus_Pa) - 1.0; }
};

/// A shaft element's Rayleigh damping, C_e = alpha M_e + beta K_e, acting in
/// the casing's frame (as ROSS's shaft elements' alpha and beta). It is a
/// structural damping to tune a model's modal damping (each mode's ratio
/// alpha / (2 w) + beta w / 2 where C is proportional throughout): a real
/// shaft's material damping turns with the shaft (internal damping, which
/// destabilises whirl above the first critical speed), which this form does
/// not model. None by default, as in ROSS.
struct ShaftDamping {
  double mass_proportional_per_s = 0.0;   ///< alpha [1/s]
  double stiffness_proportional_s = 0.0;  ///< beta [s]
};

struct ShaftElement {
  double length_m = 0.0;
  double outer_diameter_m = 0.0;
  double inner_diameter_m = 0.0;  ///< 0: solid
  Material material;
  ShaftDamping damping;
};

struct DiskElement {
  int node = 0;
  double mass_kg = 0.0;
  double polar_inertia_kg_m2 = 0.0;      ///< I_p, about the spin axis
  double diametral_inertia_kg_m2 = 0.0;  ///< I_d, about a diameter through the mass centre
  /// A uniform annulus of width w between the two diameters:
  /// m = rho pi w (od^2 - id^2) / 4, I_p = m (od^2 + id^2) / 8, I_d = I_p / 2 + m w^2 / 12.
  static DiskElement from_geometry(int node, const Material& material, double width_m, double inner_diameter_m,
                                   double outer_diameter_m);
};

/// A bearing or a seal: the coefficients at a node's x, y [N/m, N s/m, kg],
/// between the node and the ground, or between the node and link_node (ROSS's
/// n_link: a support node, or another node), where its force on the node is
/// -k (u_node - u_link) - c (...)' - m (...)''. The added mass (a seal's or a
/// squeeze film's fluid inertia) is symmetric, mxy == myx: M is a kinetic
/// energy's.
struct BearingElement {
  int node = 0;
  double kxx = 0.0, kxy = 0.0, kyx = 0.0, kyy = 0.0;
  double cxx = 0.0, cxy = 0.0, cyx = 0.0, cyy = 0.0;
  double mxx = 0.0, mxy = 0.0, myx = 0.0, myy = 0.0;
  int link_node = -1;  ///< -1: the ground
};

/// A point mass [kg] (ROSS's PointMass), mx in x and my in y. On a shaft
/// node it adds to the node's mass. On a support node, numbered on from the
/// shaft's last (nodes(), nodes() + 1, ...), it is that node's whole mass: a
/// pedestal or a bearing housing between bearings (one to the shaft by its
/// link_node, one to the ground), with an x and a y and no tilt.
struct PointMass {
  int node = 0;
  double mx_kg = 0.0, my_kg = 0.0;
};

/// An unbalance at a node: its force m e w^2 points along phase_rad (from
/// +x) at spin angle 0 and turns with the spin.
struct RotorUnbalance {
  int node = 0;
  double me_kg_m = 0.0;    ///< m e
  double phase_rad = 0.0;  ///< the force's direction at spin angle 0, from +x
};

struct RotorMatrices {
  Eigen::MatrixXd M, K, C, G;  ///< dofs() x dofs()
  int support_nodes = 0;       ///< the DOFs: 4 per shaft node, then x, y per support node
};

struct FeRotor {
  std::vector<ShaftElement> shaft;
  std::vector<DiskElement> disks;
  std::vector<BearingElement> bearings;
  std::vector<PointMass> point_masses;
  std::vector<RotorUnbalance> unbalances;
  int rub_station_node = -1;          ///< where the rotor meets the stator; -1: none named
  double rub_contact_radius_m = 0.0;  ///< R_r at the station: the rotating surface's radius there
  std::vector<int> probe_nodes;       ///< where the X/Y proximity probes sit
  /// Matrices exported by another FE program, in place of shaft, disks and
  /// bearings (assemble() returns them), with their nodes' positions.
  std::optional<RotorMatrices> imported;
  std::vector<double> imported_node_z_m;
  int imported_support_nodes = 0;  ///< their x, y after the shaft nodes' DOFs
  /// Damping given per mode of the rotor at rest (the rotor file's
  /// modal_damping): assemble() adds C = M Phi diag(2 zeta_i w_i) Phi^T M
  /// over the undamped modes of (M, K) (K's symmetric part, bearings'
  /// stiffness included; Phi M-normalised; modes below 1 rpm, rigid-body
  /// ones, left undamped, as ROSS does), so that each mode alone gets
  /// zeta_i where the rest of C is nil. zeta_i from one of:
  /// - modal_damping_ratios: the i-th natural frequency's ratio, a double
  ///   one (an isotropic rotor's two planes) counted once; every higher one
  ///   modal_damping_higher_ratio, or the last ratio without it. A fit to a
  ///   measured rotor (an impact test gives a ratio per mode). ROSS's
  ///   modal_damping_ratio lists one per eigenvalue, twins apart, and its
  ///   default_damping_ratio (0) is the higher ones'.
  /// - shaft_loss_factor eta: the shaft material's hysteretic loss as the
  ///   modal strain energy method gives it, zeta_i = (eta / 2) phi_i^T K_s
  ///   phi_i / w_i^2 with K_s the shaft elements' stiffness: a mode that
  ///   bends the shaft gets eta / 2, one that moves the rotor rigidly on its
  ///   bearings nearly none. Viscous at each mode's own frequency, in the
  ///   casing's frame (a shaft's material damping turns with it: see
  ///   ShaftDamping). Elements only: imported matrices do not say which
  ///   stiffness is the shaft's.
  /// Empty and 0: none.
  std::vector<double> modal_damping_ratios;
  std::optional<double> modal_damping_higher_ratio;
  double shaft_loss_factor = 0.0;
  int nodes() const {
    return imported ? static_cast<int>(imported_node_z_m.size()) : static_cast<int>(shaft.size()) + 1;
  }
  /// A node's position along the shaft [m]: from node 0 for elements, the
  /// file's z for imported matrices. node in [0, nodes()).
  double node_z_m(int node) const {
    if (node < 0 || node >= nodes()) throw std::out_of_range("node_z_m: node " + std::to_string(node));
    if (imported) return imported_node_z_m[static_cast<std::size_t>(node)];
    double z = 0.0;
    for (int i = 0; i < node; ++i) z += shaft[static_cast<std::size_t>(i)].length_m;
    return z;
  }
  /// Support nodes: numbered from nodes() on, each with its x and y DOFs
  /// after the shaft nodes' 4 (ROSS's order, without z).
  int support_nodes() const {
    if (imported) return imported_support_nodes;
    int n = 0;
    for (const PointMass& p : point_masses) n += p.node >= nodes() ? 1 : 0;
    return n;
  }
  int dofs() const { return 4 * nodes() + 2 * support_nodes(); }
  /// The x (kDofX) or y (kDofY) DOF of a shaft or support node.
  int translation_dof(int node, int xy) const {
    return node < nodes() ? 4 * node + xy : 4 * nodes() + 2 * (node - nodes()) + xy;
  }
};

/// The DOF index of a node's coordinate.
enum NodeDof { kDofX = 0, kDofY = 1, kDofAlpha = 2, kDofBeta = 3 };
inline int dof_index(int node, NodeDof d) { return 4 * node + d; }

/// Cowper's shear coefficient of a hollow circular section, r = id / od:
/// kappa = 6 (1 + r^2)^2 (1 + nu) / ((1 + r^2)^2 (7 + 6 nu) + r^2 (20 + 12 nu)).
double cowper_shear_coefficient(double poisson_ratio, double diameter_ratio);

using ElementMatrix = Eigen::Matrix<double, 8, 8>;
/// One shaft element's matrices, in the order [x0 y0 alpha0 beta0 x1 y1 alpha1 beta1]:
/// mass (translational plus rotary inertia), stiffness (bending with shear),
/// gyroscopic (multiplied by Omega in the equations of motion).
ElementMatrix shaft_mass(const ShaftElement& e);
ElementMatrix shaft_stiffness(const ShaftElement& e);
ElementMatrix shaft_gyroscopic(const ShaftElement& e);

/// Assembles the global matrices. Throws std::invalid_argument naming the
/// item (a disk or bearing on no node, a non-positive length or diameter).
RotorMatrices assemble(const FeRotor& rotor);

enum class ModeWhirl { kForward, kBackward, kMixed };
const char* to_string(ModeWhirl w);

struct Mode {
  double natural_frequency_rad_per_s = 0.0;  ///< w_n = |lambda|
  double damped_frequency_rad_per_s = 0.0;   ///< w_d = Im lambda
  double damping_ratio = 0.0;                ///< -Re lambda / |lambda|
  ModeWhirl whirl = ModeWhirl::kForward;
  Eigen::VectorXcd shape;  ///< the displacement part of the eigenvector (dofs() entries), largest entry 1
};

/// The modes at speed Omega, by damped frequency ascending (eigenvalues of
/// the first-order system [[0, I], [-M^-1 K, -M^-1 (C + Omega G)]] with
/// Im lambda > 0; rigid-body modes with |lambda| <= 1e-6 rad/s and
/// overdamped roots are left out: decaying roots that decay by more than
/// 1 / eps in a cycle, Im lambda <= 0.174 (-Re lambda), a damping ratio
/// above 0.985: real ones, and an overdamped pair the spin's gyroscopic
/// coupling turned complex; a root that does not decay is a mode unless it
/// is real, Im lambda <= 1e-6 |lambda|).
/// Whirl from each node's orbit: y leading x by a quarter turn's sign
/// (arg(v_y) - arg(v_x) in (-pi, 0): forward; in (0, pi): backward; a
/// straight line counts as forward), a mode forward or backward when every
/// node with motion agrees (shaft and support nodes), mixed otherwise. With
/// an expansion (the full DOFs = expansion * q, for a reduced model, whose
/// DOFs hold expanded_support_nodes), the shapes are expanded to the full
/// DOFs before the whirl is judged.
std::vector<Mode> modes(const RotorMatrices& m, double speed_rad_per_s, int count,
                        const Eigen::MatrixXd& expansion = Eigen::MatrixXd(), int expanded_support_nodes = 0);

/// The Campbell diagram: modes(m, speed, count) at each of the speeds, on up
/// to `jobs` threads (each speed alone: the same values at any number).
std::vector<std::vector<Mode>> campbell(const RotorMatrices& m, const std::vector<double>& speeds_rad_per_s, int count,
                                        unsigned jobs = 1);

/// Every eigenvalue of that first-order system at speed Omega [1/s] (M
/// positive definite; K, C and G may be any square matrices of its size,
/// the contact's linearisation among them: rk4_stability.hpp).
Eigen::VectorXcd eigenvalues(const RotorMatrices& m, double speed_rad_per_s);

/// The roots the first-order system has at speed Omega that modes() leaves
/// out (Im lambda >= 0 but the rigid-body ones, as modes() judges them),
/// from one QR:
/// - overdamped: decaying ones. A real root counts once each (an overdamped
///   pair at rest twice), a complex pair once (its Im > 0 member);
/// - diverging: growing ones, a real root of a negative stiffness or a pair
///   that grows by 1 / eps before it turns; a rotor that has one is unstable
///   at that speed;
/// - rigid_body: every root below 1 rpm (as ROSS, and the modal damping,
///   take a rigid-body mode; no mode is that slow: modal::oscillatory), of
///   either sign of Re and of Im, so two per free motion without damping: a
///   part with no stiffness path to the ground, whose zero roots
///   the QR leaves at about sqrt(eps) times the largest (1e-4 rad/s on a
///   32-DOF rotor on pedestals), as real roots or as pairs.
struct NonModeRoots {
  int overdamped = 0;
  int diverging = 0;
  int rigid_body = 0;
};
NonModeRoots non_mode_roots(const RotorMatrices& m, double speed_rad_per_s);

/// Critical speeds: where a mode's damped frequency equals the speed
/// (w_d(Omega) = Omega, the synchronous line crossing the Campbell diagram),
/// for the `count` lowest modes tracked by index, in [0, max_speed]; located
/// with TOMS 748 between the `samples` + 1 evenly spaced speeds where the
/// sign changes, from the eigenvalues alone (the modes up to 1.5 max_speed
/// by Arnoldi on a large rotor, all by the QR on a small one: modes()'s
/// paths, without the vectors' refinement). Where the number of modes
/// differs at two neighbouring speeds (an overdamped pair the spin turns
/// into modes), the interval is halved down to 1e-7 of the range around the
/// change and each part searched alone, so modes that appear with the speed
/// have their crossings too. A change that another undoes between two
/// speeds is not seen. The grid's eigenvalues on up to `jobs` threads (the
/// same values at any number).
struct CriticalSpeed {
  int mode_index = 0;
  double speed_rad_per_s = 0.0;
  ModeWhirl whirl = ModeWhirl::kForward;
  double damping_ratio = 0.0;  ///< the crossing mode's there
};
std::vector<CriticalSpeed> critical_speeds(const RotorMatrices& m, int count, double max_speed_rad_per_s,
                                           int samples = 200, unsigned jobs = 1);

}  // namespace rotor_rub::core
