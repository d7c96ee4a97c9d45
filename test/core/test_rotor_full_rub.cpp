// The synchronous full annular rub of a flexible rotor (rotor_steady_response.hpp)
// checked without its own algebra: the full FE response it returns (the
// unbalances plus the contact force it found, solved on the whole rotor)
// puts the station on the bore at distance C from the stator, with the
// contact force along the normal and the friction against the sliding, on
// circular orbits at every node; and the one-disk rotor's rub is the
// Jeffcott's (steady_response.hpp, itself checked against every method's
// runs in test_steady_response.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/rotor_steady_response.hpp"
#include "rotor_rub_sim/core/steady_response.hpp"
#include "test_support.hpp"

using namespace rotor_rub;
using cd = std::complex<double>;

namespace {

// The seal rotor made isotropic (kyy = kxx, no cross-coupling but the seal's
// skew one, which is isotropic).
core::FeRotor isotropic_seal_rotor() {
  core::FeRotor r = core::load_rotor_file(test::source_path("config/rotors/seal_rub.yaml"));
  for (auto& b : r.bearings) {
    b.kyy = b.kxx;
    b.cyy = b.cxx;
  }
  return r;
}

}  // namespace

// Both stators, two speeds: every branch is a solution of the full model.
// 1e-9 relative: the complex LU of the 52-DOF dynamic stiffness near
// resonance (condition ~1e6) in double precision.
TEST(FlexibleFullRub, EveryBranchPutsTheStationOnTheBore) {
  const core::FeRotor rotor = isotropic_seal_rotor();
  const core::RotorMatrices m = core::assemble(rotor);
  const std::vector<core::RotorUnbalance> unbalance{{3, 2e-3, 0.0}, {9, 1e-3, 1.0}};
  core::StationStator elastic;
  elastic.rigid = false;
  elastic.mass_kg = 20.0;
  elastic.stiffness_N_per_m = 5e6;
  elastic.damping_N_s_per_m = 500.0;
  const double C = 1e-4, f = 0.2;
  int branches = 0;
  for (const core::StationStator& stator : {core::StationStator{}, elastic}) {
    for (double w : {200.0, 260.0}) {
      const auto rubs = core::synchronous_full_rub(m, 6, unbalance, stator, C, f, w);
      for (const auto& s : rubs) {
        ++branches;
        const cd zr = s.response(core::dof_index(6, core::kDofX));
        EXPECT_NEAR(std::abs(zr - s.stator_m), C, 1e-9 * C) << w;
        EXPECT_GT(s.normal_force_N, 0.0);
        for (int node = 0; node < rotor.nodes(); ++node) {  // circles: y = -i x
          const cd x = s.response(core::dof_index(node, core::kDofX)),
                   y = s.response(core::dof_index(node, core::kDofY));
          EXPECT_LT(std::abs(y + cd(0, 1) * x), 1e-9 * std::abs(zr)) << node;
        }
        // The rotor's own equation, D q = f_unbalance + f_contact, with the
        // contact force rebuilt here from N and the normal the positions give.
        {
          const cd n = (zr - s.stator_m) / C;
          const cd contact = -s.normal_force_N * cd(1, f) * n;
          Eigen::VectorXcd force = Eigen::VectorXcd::Zero(m.M.rows());
          for (const auto& u : unbalance) {
            const cd fu = u.me_kg_m * w * w * std::polar(1.0, u.phase_rad);
            force(core::dof_index(u.node, core::kDofX)) += fu;
            force(core::dof_index(u.node, core::kDofY)) += cd(0, -1) * fu;
          }
          force(core::dof_index(6, core::kDofX)) += contact;
          force(core::dof_index(6, core::kDofY)) += cd(0, -1) * contact;
          const Eigen::MatrixXcd d = m.K.cast<cd>() - w * w * m.M.cast<cd>() + cd(0, w) * (m.C + w * m.G).cast<cd>();
          EXPECT_LT((d * s.response - force).cwiseAbs().maxCoeff(), 1e-9 * force.cwiseAbs().maxCoeff()) << w;
        }
        // The stator's equation: B z_s = N (1 + i f) n, n = (z_r - z_s) / C.
        if (!stator.rigid) {
          const cd b(stator.stiffness_N_per_m - stator.mass_kg * w * w, stator.damping_N_s_per_m * w);
          const cd n = (zr - s.stator_m) / C;
          EXPECT_LT(std::abs(b * s.stator_m - s.normal_force_N * cd(1, f) * n), 1e-9 * s.normal_force_N);
        }
      }
    }
  }
  EXPECT_GE(branches, 4);  // the check above had something to check
}

// The one-disk rotor (config/rotors/paper_jeffcott.yaml) against the
// Jeffcott's full rub with the disk's mass plus 17/35 of the shaft's and the
// midspan stiffness (the shaft's first mode lumped, Rayleigh): the lumping
// misses the shaft's distributed inertia at order (m_s / m)(w / w_2)^2,
// under 1e-6 here (m_s / m = 1.8e-4, far below the second mode); measured
// 1.7e-8 on N and 2.6e-9 C on the orbit.
TEST(FlexibleFullRub, OneDiskRotorIsTheJeffcotts) {
  const core::FeRotor rotor = core::load_rotor_file(test::source_path("config/rotors/paper_jeffcott.yaml"));
  const core::RotorMatrices m = core::assemble(rotor);
  const core::ShaftElement& e = rotor.shaft[0];
  const double L = 2 * e.length_m, d = e.outer_diameter_m, A = M_PI * d * d / 4, I = M_PI * std::pow(d, 4) / 64;
  const double kappa = core::cowper_shear_coefficient(e.material.poisson_ratio(), 0.0);
  core::ModelParameters p;
  p.rotor_stiffness_N_per_m =
      1.0 / (L * L * L / (48 * e.material.youngs_modulus_Pa * I) + L / (4 * kappa * e.material.shear_modulus_Pa * A) +
             1.0 / (2 * rotor.bearings[0].kxx));
  p.rotor_mass_kg = rotor.disks[0].mass_kg + 17.0 / 35.0 * e.material.density_kg_per_m3 * A * L;
  p.rotor_damping_N_s_per_m = 0.0;
  p.stator_model = core::StatorModel::kRigid;
  p.friction_coefficient = 0.3;
  p.clearance_m = 0.3e-3;
  const double me = p.rotor_mass_kg * p.eccentricity_m;
  for (double w : {60.0, 100.0}) {
    const auto want = core::synchronous_full_rub(p, w);
    const auto got = core::synchronous_full_rub(m, 1, {{1, me, 0.0}}, core::StationStator{}, p.clearance_m,
                                                p.friction_coefficient, w);
    ASSERT_EQ(got.size(), want.size()) << w;
    ASSERT_FALSE(got.empty()) << w;
    for (std::size_t k = 0; k < got.size(); ++k) {
      EXPECT_NEAR(got[k].normal_force_N / want[k].normal_force_N, 1.0, 1e-6) << w;
      EXPECT_LT(std::abs(got[k].station_m - want[k].rotor_m), 1e-6 * p.clearance_m) << w;
    }
  }
}

TEST(FlexibleFullRub, AnisotropicRotorIsRefused) {
  const core::FeRotor rotor = core::load_rotor_file(test::source_path("config/rotors/seal_rub.yaml"));
  try {
    core::synchronous_full_rub(core::assemble(rotor), 6, {{3, 1e-3, 0.0}}, core::StationStator{}, 1e-4, 0.1, 200.0);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not isotropic"), std::string::npos) << e.what();
  }
}
