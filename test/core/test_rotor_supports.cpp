// Support nodes, point masses and bearings' added mass (fe_rotor.hpp's
// PointMass and BearingElement, the rotor file's point_masses and link_node,
// the matrices' support_nodes), against closed forms: a short stiff rotor
// bouncing on bearings that stand on pedestals is a two-mass chain per plane;
// a bearing's added mass adds to the bounce's mass; the reduction keeps the
// pedestals (its full basis is the full model, gravity's sag included); the
// matrices of a rotor on pedestals import as its element file; bad files.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <sstream>

#include "rotor_file_support.hpp"
#include "rotor_rub_sim/core/fe_rotor.hpp"
#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/rotor_reduction.hpp"

using namespace rotor_rub;

namespace {

// A short thick rotor, 0.1 m long and 0.3 m across (55.2 kg): its bending
// stiffness (about 1e11 N/m) is 1e5 times the bearings', so it bounces as a
// rigid body to about 1e-5 of w^2.
constexpr double kLength_m = 0.1, kDiameter_m = 0.3;
constexpr double kBearing_N_per_m = 1e6, kPedestal_N_per_m = 4e6;
constexpr double kPedestalX_kg = 20.0, kPedestalY_kg = 30.0;
// The rotor's own flexibility (above), which the rigid closed form leaves out.
constexpr double kRigidBodyTolerance = 1e-4;

const char* const kRotorOnPedestals =
    "shaft:\n  - {length_m: 0.1, outer_diameter_m: 0.3}\n"
    "point_masses:\n  - {node: 2, mx_kg: 20, my_kg: 30}\n  - {node: 3, mx_kg: 20, my_kg: 30}\n"
    "bearings:\n"
    "  - {node: 0, link_node: 2, kxx: 1e6, kyy: 1e6}\n  - {node: 1, link_node: 3, kxx: 1e6, kyy: 1e6}\n"
    "  - {node: 2, kxx: 4e6, kyy: 4e6}\n  - {node: 3, kxx: 4e6, kyy: 4e6}\n";

using test::load_error;
using test::write_file;

// The message a call is refused with (std::invalid_argument), or "accepted".
template <class F>
std::string refusal_of(F&& call) {
  try {
    call();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

// The bounce of a rigid rotor m_r on two bearings k_b, each on a pedestal
// m_p on a spring k_p (both pedestals in phase): M = diag(m_r, 2 m_p),
// K = [[2 k_b, -2 k_b], [-2 k_b, 2 k_b + 2 k_p]]; its two w^2, ascending.
std::pair<double, double> bounce_w2(double m_r, double m_p) {
  const double a = m_r * 2.0 * m_p;
  const double b = -(m_r * (2.0 * kBearing_N_per_m + 2.0 * kPedestal_N_per_m) + 2.0 * m_p * 2.0 * kBearing_N_per_m);
  const double c = 4.0 * kBearing_N_per_m * kPedestal_N_per_m;
  const double root = std::sqrt(b * b - 4.0 * a * c);
  return {(-b - root) / (2.0 * a), (-b + root) / (2.0 * a)};
}

// Whether the rotor has an undamped mode of w^2 within the rigid body's tolerance.
bool has_mode(const std::vector<core::Mode>& modes, double w2) {
  for (const core::Mode& m : modes) {
    const double got = m.natural_frequency_rad_per_s * m.natural_frequency_rad_per_s;
    if (std::abs(got - w2) <= kRigidBodyTolerance * w2) return true;
  }
  return false;
}

}  // namespace

TEST(RotorSupports, ARotorOnPedestalsBouncesAsATwoMassChainInEachPlane) {
  const core::FeRotor rotor = core::load_rotor_file(write_file("pedestals.yaml", kRotorOnPedestals));
  ASSERT_EQ(rotor.nodes(), 2);
  ASSERT_EQ(rotor.support_nodes(), 2);
  ASSERT_EQ(rotor.dofs(), 12);
  const core::RotorMatrices m = core::assemble(rotor);
  const double m_r = m.M(0, 0) + m.M(4, 4) + 2.0 * m.M(0, 4);  // the rigid translation's mass
  ASSERT_NEAR(m_r, 7810.0 * M_PI / 4.0 * kDiameter_m * kDiameter_m * kLength_m, 1e-9 * m_r);
  const std::vector<core::Mode> modes = core::modes(m, 0.0, 8);
  for (const double m_p : {kPedestalX_kg, kPedestalY_kg}) {  // x's chain, then y's
    const auto [low, high] = bounce_w2(m_r, m_p);
    EXPECT_TRUE(has_mode(modes, low)) << "pedestal " << m_p << " kg: w " << std::sqrt(low);
    EXPECT_TRUE(has_mode(modes, high)) << "pedestal " << m_p << " kg: w " << std::sqrt(high);
  }
  // Without the pedestals' mass the two planes would bounce alike.
  EXPECT_FALSE(has_mode(modes, bounce_w2(m_r, 0.5 * (kPedestalX_kg + kPedestalY_kg)).first));
  // The link's sign (which the frequencies cannot tell: a support DOF turned
  // over leaves them as they are): pushed at the shaft, the pedestal gives
  // way the same way, by its spring's share, k_b / (k_b + k_p) of the
  // bearing node's static deflection (the shaft near rigid).
  Eigen::VectorXd push = Eigen::VectorXd::Zero(rotor.dofs());
  push(rotor.translation_dof(0, core::kDofX)) = push(rotor.translation_dof(1, core::kDofX)) = 1.0;
  const Eigen::VectorXd u = m.K.partialPivLu().solve(push);
  const double shaft = u(rotor.translation_dof(0, core::kDofX)), pedestal = u(rotor.translation_dof(2, core::kDofX));
  EXPECT_NEAR(pedestal / shaft, kBearing_N_per_m / (kBearing_N_per_m + kPedestal_N_per_m), kRigidBodyTolerance);
}

TEST(RotorSupports, ABearingsAddedMassAddsToTheBounce) {
  auto rotor_with = [](const std::string& bearing_extra) {
    return core::assemble(core::load_rotor_file(
        write_file("added_mass.yaml",
                   "shaft:\n  - {length_m: 0.1, outer_diameter_m: 0.3}\nbearings:\n"
                   "  - {node: 0, kxx: 1e6, kyy: 1e6" +
                       bearing_extra + "}\n  - {node: 1, kxx: 1e6, kyy: 1e6" + bearing_extra + "}\n")));
  };
  const core::RotorMatrices bare = rotor_with(""), added = rotor_with(", mxx: 5, myy: 5");
  const double m_r = bare.M(0, 0) + bare.M(4, 4) + 2.0 * bare.M(0, 4);
  const std::vector<core::Mode> modes = core::modes(added, 0.0, 4);
  EXPECT_TRUE(has_mode(modes, 2.0 * kBearing_N_per_m / (m_r + 10.0)));
  EXPECT_FALSE(has_mode(modes, 2.0 * kBearing_N_per_m / m_r));
  // A shaft node's point mass is the same added mass.
  const core::RotorMatrices point = core::assemble(core::load_rotor_file(
      write_file("point_mass.yaml",
                 "shaft:\n  - {length_m: 0.1, outer_diameter_m: 0.3}\n"
                 "point_masses:\n  - {node: 0, mass_kg: 5}\n  - {node: 1, mass_kg: 5}\n"
                 "bearings:\n  - {node: 0, kxx: 1e6, kyy: 1e6}\n  - {node: 1, kxx: 1e6, kyy: 1e6}\n")));
  EXPECT_EQ(point.M, added.M);
  // Between the shaft and a pedestal the added mass acts on their relative
  // motion: moving together, they carry none of it.
  const core::FeRotor linked = core::load_rotor_file(write_file(
      "linked_added_mass.yaml", std::string(kRotorOnPedestals) + "  - {node: 0, link_node: 2, mxx: 7, myy: 7}\n"));
  const core::FeRotor unlinked = core::load_rotor_file(write_file("pedestals.yaml", kRotorOnPedestals));
  const Eigen::MatrixXd added_m = core::assemble(linked).M - core::assemble(unlinked).M;
  Eigen::VectorXd together = Eigen::VectorXd::Zero(linked.dofs()), apart = together;
  together(linked.translation_dof(0, core::kDofX)) = together(linked.translation_dof(2, core::kDofX)) = 1.0;
  apart(linked.translation_dof(0, core::kDofX)) = 1.0;
  EXPECT_EQ(together.dot(added_m * together), 0.0);
  EXPECT_EQ(apart.dot(added_m * apart), 7.0);
}

// A support node without its bearing to the ground leaves the rotor free:
// its rigid-body roots, which the QR leaves near 0 of either sign (about
// 1e-4 rad/s here), are counted as such, not as a divergence, and are no
// mode (each mode found is above 1 rpm, at rest and at speed).
TEST(RotorSupports, AFreePedestalIsRigidBodyMotionNotADivergence) {
  const std::string shaft_on_pedestals =
      "shaft:\n  - {length_m: 0.1, outer_diameter_m: 0.3}\n"
      "point_masses:\n  - {node: 2, mass_kg: 20}\n  - {node: 3, mass_kg: 20}\n"
      "bearings:\n  - {node: 0, link_node: 2, kxx: 1e6, kyy: 1e6, cxx: 100, cyy: 100}\n"
      "  - {node: 1, link_node: 3, kxx: 1e6, kyy: 1e6, cxx: 100, cyy: 100}\n";
  const core::RotorMatrices free_rotor =
      core::assemble(core::load_rotor_file(write_file("free_pedestals.yaml", shaft_on_pedestals)));
  const core::NonModeRoots free = core::non_mode_roots(free_rotor, 0.0);
  EXPECT_EQ(free.diverging, 0);
  // Per plane the shaft's translation and its tilt, each pedestal following
  // its bearing's node: four free motions, each a double zero root.
  EXPECT_EQ(free.rigid_body, 8);
  constexpr double kOneRpm_rad_per_s = 2.0 * M_PI / 60.0;
  for (const double speed : {0.0, 300.0}) {
    const std::vector<core::Mode> modes = core::modes(free_rotor, speed, 24);
    ASSERT_FALSE(modes.empty()) << speed;
    for (const core::Mode& md : modes) {
      EXPECT_GT(md.natural_frequency_rad_per_s, kOneRpm_rad_per_s) << speed;
    }
  }
  const core::NonModeRoots grounded =
      core::non_mode_roots(core::assemble(core::load_rotor_file(write_file(
                               "grounded_pedestals.yaml", shaft_on_pedestals + "  - {node: 2, kxx: 4e6, kyy: 4e6}\n"
                                                                               "  - {node: 3, kxx: 4e6, kyy: 4e6}\n"))),
                           0.0);
  EXPECT_EQ(grounded.rigid_body, 0);
  EXPECT_EQ(grounded.diverging, 0);
}

// Reduced to every planar mode (the basis spans every DOF) the rotor on
// pedestals is the full model: its modes, and under gravity its sag, the
// pedestals' weight included.
TEST(RotorSupports, TheReductionKeepsThePedestals) {
  const core::FeRotor rotor = core::load_rotor_file(
      write_file("pedestals_isotropic.yaml",
                 "shaft:\n  - {elements: 4, length_m: 0.25, outer_diameter_m: 0.05}\n"
                 "disks:\n  - {node: 2, mass_kg: 10, polar_inertia_kg_m2: 0.05, diametral_inertia_kg_m2: 0.03}\n"
                 "point_masses:\n  - {node: 5, mass_kg: 20}\n  - {node: 6, mass_kg: 25}\n"
                 "bearings:\n"
                 "  - {node: 0, link_node: 5, kxx: 1e6, kyy: 3e6, cxx: 100, cyy: 100}\n"
                 "  - {node: 4, link_node: 6, kxx: 1e6, kyy: 3e6, cxx: 100, cyy: 100}\n"
                 "  - {node: 5, kxx: 5e6, kyy: 8e6}\n  - {node: 6, kxx: 5e6, kyy: 8e6}\n"));
  ASSERT_EQ(core::max_planar_modes(rotor), 12);  // x, beta of 5 shaft nodes, x of 2 pedestals
  const core::RotorMatrices full = core::assemble(rotor);
  const core::ReducedRotor reduced = core::reduce_rotor(rotor, full, 2, core::max_planar_modes(rotor));
  const auto want = core::modes(full, 300.0, 10), got = core::modes(reduced, 300.0, 10);
  ASSERT_EQ(got.size(), want.size());
  // A change of basis: the eigenvalues agree to the solver's rounding.
  constexpr double kSameRotor = 1e-9;
  for (std::size_t i = 0; i < want.size(); ++i) {
    EXPECT_NEAR(got[i].damped_frequency_rad_per_s, want[i].damped_frequency_rad_per_s,
                kSameRotor * want[i].damped_frequency_rad_per_s)
        << i;
  }
  // Gravity's sag at the station: K q = -g M 1_y in full, and in the
  // reduced coordinates with their unit weight.
  constexpr double g = 9.81;
  Eigen::VectorXd ones_y = Eigen::VectorXd::Zero(rotor.dofs());
  for (int node = 0; node < rotor.nodes() + rotor.support_nodes(); ++node) ones_y(rotor.translation_dof(node, 1)) = 1;
  const Eigen::VectorXd sag_full = full.K.partialPivLu().solve(-g * (full.M * ones_y));
  const Eigen::VectorXd sag_reduced =
      reduced.expansion * reduced.matrices.K.partialPivLu().solve(-g * reduced.unit_weight_kg);
  const int y = core::dof_index(2, core::kDofY);
  EXPECT_NEAR(sag_reduced(y), sag_full(y), kSameRotor * std::abs(sag_full(y)));
  EXPECT_GT(std::abs(sag_full(rotor.translation_dof(5, 1))), 0.0);  // the pedestal sags too
}

// The matrices of a rotor on pedestals, 4 DOF per shaft node and 2 per
// support node, are its element file; ROSS's 6 and 3 drop z and theta.
TEST(RotorSupports, PedestalMatricesImportAsTheirElementFile) {
  const core::FeRotor elements = core::load_rotor_file(write_file("pedestals.yaml", kRotorOnPedestals));
  const core::RotorMatrices m = core::assemble(elements);
  auto rows = [](const Eigen::MatrixXd& x) {
    std::ostringstream os;
    os.precision(17);
    for (int i = 0; i < x.rows(); ++i) {
      os << "    - [";
      for (int j = 0; j < x.cols(); ++j) os << (j ? ", " : "") << x(i, j);
      os << "]\n";
    }
    return os.str();
  };
  const std::string four = "matrices:\n  nodes_z_m: [0, 0.1]\n  support_nodes: 2\n  M:\n" + rows(m.M) + "  K:\n" +
                           rows(m.K) + "  C:\n" + rows(m.C) + "  G:\n" + rows(m.G);
  const core::FeRotor imported = core::load_rotor_file(write_file("pedestal_matrices.yaml", four));
  EXPECT_EQ(imported.support_nodes(), 2);
  const core::RotorMatrices back = core::assemble(imported);
  EXPECT_EQ(back.M, m.M);
  EXPECT_EQ(back.K, m.K);
  // ROSS's order: [x, y, z, alpha, beta, theta] per shaft node, [x, y, z]
  // per support node, z and theta with their own mass and stiffness.
  std::vector<int> lateral;
  for (int node = 0; node < 2; ++node) {
    for (const int d : {0, 1, 3, 4}) lateral.push_back(6 * node + d);
  }
  for (int k = 0; k < 2; ++k) {
    lateral.push_back(12 + 3 * k);
    lateral.push_back(12 + 3 * k + 1);
  }
  auto six = [&](const Eigen::MatrixXd& x, double own) {
    Eigen::MatrixXd out = own * Eigen::MatrixXd::Identity(18, 18);
    for (std::size_t a = 0; a < lateral.size(); ++a) {
      for (std::size_t b = 0; b < lateral.size(); ++b) out(lateral[a], lateral[b]) = x(a, b);
    }
    return out;
  };
  const std::string ross = "matrices:\n  nodes: [0, 0.1]\n  support_nodes: 2\n  M:\n" + rows(six(m.M, 3.0)) + "  K:\n" +
                           rows(six(m.K, 1e8)) + "  C:\n" + rows(six(m.C, 0.0)) + "  G:\n" + rows(six(m.G, 0.0));
  const core::RotorMatrices from_ross = core::assemble(core::load_rotor_file(write_file("pedestal_ross.yaml", ross)));
  EXPECT_EQ(from_ross.M, m.M);
  EXPECT_EQ(from_ross.K, m.K);
  EXPECT_NE(load_error("point_masses:\n  - {node: 0, mass_kg: 1}\n" + four)
                .find("gives both 'matrices' and "
                      "'point_masses'"),
            std::string::npos);
}

TEST(RotorSupports, BadSupportsNameTheItemTheKeyAndTheRange) {
  const std::string shaft = "shaft:\n  - {length_m: 0.1, outer_diameter_m: 0.3}\n";
  auto error_of = [&](const std::string& rest) { return load_error(shaft + rest); };
  // A support node past the next one (node 3 with no node 2): one point
  // mass makes at most one support node.
  EXPECT_NE(error_of("point_masses:\n  - {node: 3, mass_kg: 20}\n")
                .find("point mass 0 key 'node': value 3 is out of range; accepted: [0, 2]"),
            std::string::npos);
  // Two on one support node; a support node out of turn.
  EXPECT_NE(error_of("point_masses:\n  - {node: 3, mass_kg: 20}\n  - {node: 3, mass_kg: 20}\n")
                .find("point mass 1 key 'node': value 3 is a support node that has a point mass already; accepted: "
                      "one point mass per support node"),
            std::string::npos)
      << error_of("point_masses:\n  - {node: 3, mass_kg: 20}\n  - {node: 3, mass_kg: 20}\n");
  EXPECT_NE(
      error_of("point_masses:\n  - {node: 3, mass_kg: 20}\n  - {node: 0, mass_kg: 2}\n")
          .find("point mass 0 key 'node': value 3 leaves a gap; accepted: support nodes numbered in turn, 2 to 2"),
      std::string::npos)
      << error_of("point_masses:\n  - {node: 3, mass_kg: 20}\n  - {node: 0, mass_kg: 2}\n");
  // The same, built in code: assemble() refuses it.
  core::FeRotor gap = core::load_rotor_file(write_file("one_pedestal.yaml", shaft));
  gap.point_masses = {{3, 20.0, 20.0}, {0, 2.0, 2.0}};
  const std::string out_of_turn = refusal_of([&] { core::assemble(gap); });
  EXPECT_NE(out_of_turn.find("point mass 0: node 3 is out of range; accepted: 0 to 1 (a shaft node) or the next "
                             "support node, 2 on, one point mass each"),
            std::string::npos)
      << out_of_turn;
  EXPECT_NE(error_of("point_masses:\n  - {node: 2, mx_kg: 20, my_kg: 0}\n")
                .find("point mass 0: support node 2 has mx_kg 20.000000, my_kg 0.000000; accepted: both > 0 (its "
                      "whole mass)"),
            std::string::npos);
  EXPECT_NE(error_of("point_masses:\n  - {node: 0, mass_kg: 2, mx_kg: 3}\n")
                .find("point mass 0 gives both 'mass_kg' and 'mx_kg'/'my_kg'; accepted: mass_kg, or mx_kg and my_kg"),
            std::string::npos);
  EXPECT_NE(error_of("bearings:\n  - {node: 0, link_node: 0, kxx: 1e6}\n")
                .find("bearing 0 key 'link_node': value 0 is not another node; accepted: a node number other than "
                      "'node', or -1 (the ground)"),
            std::string::npos);
  EXPECT_NE(error_of("bearings:\n  - {node: 0, link_node: 2, kxx: 1e6}\n")
                .find("bearing 0 key 'link_node': value 2 is out of range; accepted: [-1, 1]"),
            std::string::npos)
      << error_of("bearings:\n  - {node: 0, link_node: 2, kxx: 1e6}\n");
  EXPECT_NE(error_of("bearings:\n  - {node: 0, kxx: 1e6, mxx: 1, myy: 1, mxy: 0.5, myx: -0.5}\n")
                .find("accepted: mxy == myx and mxy^2 <= mxx myy"),
            std::string::npos);
  EXPECT_NE(error_of("bearings:\n  - {node: 0, kxx: 1e6, mxx: 1, myy: 1, mxy: 2, myx: 2}\n")
                .find("accepted: mxy == myx and mxy^2 <= mxx myy"),
            std::string::npos);
  // A run's reduction needs one mass in x and y (the contact's station
  // mass): a run's loading names the point mass, the reduction the planes.
  core::RotorSettings run;
  run.file = write_file("pedestals_run.yaml",
                        std::string(kRotorOnPedestals) + "rub_station: {node: 0, contact_radius_m: 0.15}\n");
  const std::string in_a_run = refusal_of([&] { core::load_flexible_rotor(run, 0.0, 100.0, 100.0, 0.0); });
  EXPECT_NE(in_a_run.find("point mass 0 (node 2) has mx_kg 20.000000, my_kg 30.000000; a run needs them equal (its "
                          "modal analysis takes any); accepted: mass_kg"),
            std::string::npos)
      << in_a_run;
  const core::FeRotor anisotropic = core::load_rotor_file(write_file("pedestals.yaml", kRotorOnPedestals));
  const std::string reduced = refusal_of([&] { core::reduce_rotor(anisotropic, core::assemble(anisotropic), 0, 2); });
  EXPECT_NE(reduced.find("a point mass or a bearing's added mass that differs in x and y"), std::string::npos)
      << reduced;
  // A rub station on a support node: shaft nodes only (as a disk's, an
  // unbalance's and a probe's, read alike).
  EXPECT_NE(error_of("point_masses:\n  - {node: 2, mass_kg: 20}\n"
                     "rub_station: {node: 2, contact_radius_m: 0.1}\n")
                .find("rub_station key 'node': value 2 is out of range; accepted: [0, 1]"),
            std::string::npos)
      << error_of("point_masses:\n  - {node: 2, mass_kg: 20}\nrub_station: {node: 2, contact_radius_m: 0.1}\n");
}
