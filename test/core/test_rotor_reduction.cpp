// The reduced flexible rotor (rotor_reduction.hpp): the coordinates it
// promises (an isotropic station mass uncoupled from the modes), exactness
// with every mode kept, the station's static stiffness exact for any number
// of modes when the bearings are isotropic, convergence of frequencies and
// unbalance responses (at the station and at the bearings' probes) as modes
// are added, and the one-disk rotor reduced to its station being the
// Jeffcott (mass and stiffness in closed form).
#include <gtest/gtest.h>

#include <cmath>

#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/rotor_reduction.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

core::FeRotor rotor_file(const std::string& name) {
  return core::load_rotor_file(test::source_path("config/rotors/" + name));
}

constexpr int kSealNode = 6;  // config/rotors/seal_rub.yaml's seal, the rub station

// Roundoff of the dense products Psi^T M Psi over ~50 DOF whose masses and
// inertias span 1e4: a few hundred eps of the largest entry.
constexpr double kStructureTolerance = 1e-12;

}  // namespace

// M = diag(m_st, m_st, I) whatever the bearings (the seal's cross-coupling,
// the bearings' kxx != kyy): every planar shape comes with its twin.
TEST(RotorReduction, StationMassIsIsotropicAndUncoupled) {
  for (const auto& [name, station] :
       {std::pair<std::string, int>{"seal_rub.yaml", kSealNode}, {"ross_example.yaml", 3}}) {
    const core::FeRotor rotor = rotor_file(name);
    const core::RotorMatrices full = core::assemble(rotor);
    for (int modes : {1, 2, 4, 9}) {
      const core::ReducedRotor r = core::reduce_rotor(rotor, full, station, modes);
      const Eigen::MatrixXd& m = r.matrices.M;
      ASSERT_EQ(m.rows(), 2 * modes);
      const double ms = r.station_mass_kg;
      EXPECT_GT(ms, 0.0);
      EXPECT_NEAR(m(1, 1), ms, kStructureTolerance * ms) << name << " " << modes;
      EXPECT_NEAR(m(0, 1), 0.0, kStructureTolerance * ms) << name << " " << modes;
      if (modes > 1) {
        EXPECT_LT(m.topRightCorner(2, 2 * modes - 2).cwiseAbs().maxCoeff(), kStructureTolerance * ms) << name;
        const Eigen::MatrixXd eye = Eigen::MatrixXd::Identity(2 * modes - 2, 2 * modes - 2);
        EXPECT_LT((m.bottomRightCorner(2 * modes - 2, 2 * modes - 2) - eye).cwiseAbs().maxCoeff(), kStructureTolerance)
            << name;
      }
      // The station's rows of the expansion are the identity: u is physical.
      EXPECT_DOUBLE_EQ(r.expansion(core::dof_index(station, core::kDofX), 0), 1.0);
      EXPECT_DOUBLE_EQ(r.expansion(core::dof_index(station, core::kDofY), 1), 1.0);
      EXPECT_EQ(r.expansion.row(core::dof_index(station, core::kDofX)).cwiseAbs().sum(), 1.0);
      EXPECT_EQ(r.expansion.row(core::dof_index(station, core::kDofY)).cwiseAbs().sum(), 1.0);
    }
  }
}

// Every mode kept spans the full space: the reduced model is the full one in
// other coordinates, so its modes are the same to the eigensolver's
// accuracy (1e-9 relative; measured 1e-12), at rest and at speed (with the
// gyroscopics and the seal's cross-coupling).
TEST(RotorReduction, AllModesKeptIsTheFullModel) {
  const core::FeRotor rotor = rotor_file("seal_rub.yaml");
  const core::RotorMatrices full = core::assemble(rotor);
  const core::ReducedRotor r = core::reduce_rotor(rotor, full, kSealNode, core::max_planar_modes(rotor));
  ASSERT_EQ(r.size(), full.M.rows());
  for (double speed : {0.0, 1000.0}) {
    const auto want = core::modes(full, speed, 8);
    const auto got = core::modes(r, speed, 8);
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t k = 0; k < want.size(); ++k) {
      EXPECT_NEAR(got[k].damped_frequency_rad_per_s / want[k].damped_frequency_rad_per_s, 1.0, 1e-9)
          << speed << " " << k;
      EXPECT_NEAR(got[k].damping_ratio, want[k].damping_ratio, 1e-9) << speed << " " << k;
      EXPECT_EQ(got[k].whirl, want[k].whirl) << speed << " " << k;
    }
  }
}

// The constraint modes are the rotor's static shapes under a station
// displacement, so with isotropic bearings (no cross-coupling) the
// station's static compliance is exact with any number of modes: K's
// inverse's station block. 1e-9 relative: the bearings' 1e7 N/m against the
// shaft's ~1e5 N/m at midspan make K's condition ~1e7 (measured 1e-13).
// With the seal example's own bearings (kxx != kyy) one planar mode (the
// planes' mean static shape) is approximate.
TEST(RotorReduction, StationStaticCompliancesExactWithIsotropicBearings) {
  core::FeRotor rotor = rotor_file("seal_rub.yaml");
  auto station_compliance = [](const Eigen::MatrixXd& k, int x) {
    const Eigen::MatrixXd inv = k.inverse();
    return Eigen::Matrix2d(inv.block<2, 2>(x, x));
  };
  {
    const core::RotorMatrices full = core::assemble(rotor);
    const Eigen::Matrix2d want = station_compliance(full.K, core::dof_index(kSealNode, core::kDofX));
    const core::ReducedRotor r = core::reduce_rotor(rotor, full, kSealNode, 1);
    EXPECT_GT((station_compliance(r.matrices.K, 0) - want).cwiseAbs().maxCoeff(), 1e-6 * want.cwiseAbs().maxCoeff())
        << "the anisotropic bearings' static compliance is not the basis's";
  }
  for (auto& b : rotor.bearings) {
    b.kyy = b.kxx;
    b.kxy = b.kyx = 0.0;
  }
  const core::RotorMatrices full = core::assemble(rotor);
  const Eigen::Matrix2d want = station_compliance(full.K, core::dof_index(kSealNode, core::kDofX));
  for (int modes : {1, 2, 5}) {
    const core::ReducedRotor r = core::reduce_rotor(rotor, full, kSealNode, modes);
    const Eigen::Matrix2d got = station_compliance(r.matrices.K, 0);
    EXPECT_LT((got - want).cwiseAbs().maxCoeff(), 1e-9 * want.cwiseAbs().maxCoeff()) << modes;
  }
}

// Adding modes converges: the first four frequencies (at rest and at
// 1000 rad/s, relative) and the unbalance response at the station and at
// the two bearings' probes (an unbalance on the first disk, at 0.9 and 1.5
// times the first critical speed; relative to the rotor's largest
// displacement at that speed, since a probe near a node of the response
// reads a small difference of modes). Each doubling of the modes shrinks the
// worst error at least 3 times (measured 12, 35 and 190 times), and 16 planar
// modes (32 coordinates of the full 52) are within 1e-4 (measured 2.2e-6).
TEST(RotorReduction, FrequenciesAndResponsesConvergeWithModes) {
  const core::FeRotor rotor = rotor_file("seal_rub.yaml");
  const core::RotorMatrices full = core::assemble(rotor);
  const auto criticals = core::critical_speeds(full, 2, 1000.0, 10);
  ASSERT_FALSE(criticals.empty());
  const double first_critical_rad_per_s = criticals[0].speed_rad_per_s;
  auto worst_error = [&](const core::ReducedRotor& r) {
    double worst = 0.0;
    for (double speed : {0.0, 1000.0}) {
      const auto want = core::modes(full, speed, 4);
      const auto got = core::modes(r, speed, 4);
      if (got.size() < want.size()) return 1.0;
      for (std::size_t k = 0; k < want.size(); ++k) {
        worst = std::max(worst, std::abs(got[k].damped_frequency_rad_per_s / want[k].damped_frequency_rad_per_s - 1));
      }
    }
    for (double ratio : {0.9, 1.5}) {
      const double w = ratio * first_critical_rad_per_s;
      const Eigen::VectorXcd want = core::unbalance_response(full, {{3, 1e-4, 0.0}}, w);
      const Eigen::VectorXcd got = core::unbalance_response(r, {{3, 1e-4, 0.0}}, w);
      double largest = 0.0;
      for (int node = 0; node < rotor.nodes(); ++node) {
        for (auto dof : {core::kDofX, core::kDofY})
          largest = std::max(largest, std::abs(want(core::dof_index(node, dof))));
      }
      for (int node : {kSealNode, 0, 12}) {
        for (auto dof : {core::kDofX, core::kDofY}) {
          const int i = core::dof_index(node, dof);
          worst = std::max(worst, std::abs(got(i) - want(i)) / largest);
        }
      }
    }
    return worst;
  };
  double previous = 1.0;  // the first model (2 planar modes) already within 1/3
  for (int modes : {2, 4, 8, 16}) {
    const double error = worst_error(core::reduce_rotor(rotor, full, kSealNode, modes));
    EXPECT_LT(error, previous / 3.0) << modes;
    previous = error;
  }
  EXPECT_LT(previous, 1e-4);
}

// The paper's Jeffcott as a one-disk FE rotor (config/rotors/paper_jeffcott.yaml)
// reduced to its station (one planar mode, Guyan): the station's stiffness
// is the midspan one with shear and the bearings (test_fe_rotor.cpp's
// closed form; exact, the constraint mode being the static shape: 1e-9
// for the roundoff of the 1e8 N/m bearings against 2493 N/m), its mass the
// disk's plus 17/35 of the shaft's (Rayleigh's share for the Euler-Bernoulli
// static shape). What that share leaves out, relative to the total mass
// (the shaft is 1.8e-4 of it): the shape's shear part (-7e-9), the shaft's
// rotary inertia (+5.5e-9), the bearings' compliance (+6e-10): 1e-8 bounds
// each.
TEST(RotorReduction, OneDiskRotorAtItsStationIsTheJeffcott) {
  const core::FeRotor rotor = rotor_file("paper_jeffcott.yaml");
  const core::ReducedRotor r = core::reduce_rotor(rotor, core::assemble(rotor), 1, 1);
  const core::ShaftElement& e = rotor.shaft[0];
  const double L = 2 * e.length_m, d = e.outer_diameter_m, A = M_PI * d * d / 4, I = M_PI * std::pow(d, 4) / 64;
  const double kappa = core::cowper_shear_coefficient(e.material.poisson_ratio(), 0.0);
  const double k = 1.0 / (L * L * L / (48 * e.material.youngs_modulus_Pa * I) +
                          L / (4 * kappa * e.material.shear_modulus_Pa * A) + 1.0 / (2 * rotor.bearings[0].kxx));
  const double m = rotor.disks[0].mass_kg + 17.0 / 35.0 * e.material.density_kg_per_m3 * A * L;
  EXPECT_NEAR(r.matrices.K(0, 0) / k, 1.0, 1e-9);
  EXPECT_NEAR(r.matrices.K(1, 1) / k, 1.0, 1e-9);
  EXPECT_NEAR(r.station_mass_kg / m, 1.0, 1e-8);
}

TEST(RotorReduction, BadRequestsNameTheValueAndTheRange) {
  const core::FeRotor rotor = rotor_file("seal_rub.yaml");
  const core::RotorMatrices full = core::assemble(rotor);
  auto error = [&](const core::FeRotor& r, const core::RotorMatrices& m, int station, int modes) {
    try {
      core::reduce_rotor(r, m, station, modes);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(error(rotor, full, 13, 2).find("node 13 is out of range; accepted: 0 to 12"), std::string::npos);
  EXPECT_NE(error(rotor, full, 6, 0).find("0 is out of range; accepted: 1 to 26"), std::string::npos);
  EXPECT_NE(error(rotor, full, 6, 27).find("27 is out of range"), std::string::npos);
  // One bearing, at the station: held there, the rotor pivots freely.
  core::FeRotor pivot = rotor;
  pivot.bearings = {rotor.bearings[2]};
  EXPECT_NE(error(pivot, core::assemble(pivot), 6, 2).find("cannot stand"), std::string::npos)
      << error(pivot, core::assemble(pivot), 6, 2);
  EXPECT_THROW(core::unbalance_response(full, {{13, 1e-4, 0.0}}, 100.0), std::invalid_argument);
  // Imported matrices whose y-z plane is not the x-z plane's twin (a mass
  // added to y alone): the promised M = diag(m_st, m_st, I) cannot hold.
  core::FeRotor lopsided;
  lopsided.imported = full;
  lopsided.imported->M(core::dof_index(3, core::kDofY), core::dof_index(3, core::kDofY)) += 1.0;
  for (int node = 0; node < rotor.nodes(); ++node) lopsided.imported_node_z_m.push_back(rotor.node_z_m(node));
  EXPECT_NE(error(lopsided, *lopsided.imported, 6, 2).find("not the same in its x-z and y-z planes"), std::string::npos)
      << error(lopsided, *lopsided.imported, 6, 2);
}

// Bearings 115 times stiffer vertically than horizontally (a test rig's
// oil-film bearings, issue 51): a basis of one plane's shapes, or of the
// planes' mean, cannot hold both planes' static shapes and modes; this one
// does. The station's static compliance is exact once the static
// correction is in (ordered by its Rayleigh quotient: here after the first
// modes, so from 4 planar modes; 1e-9 for the conditioning, as for
// isotropic bearings above). The unbalance response at the station and the
// probes, at 0.9 and 1.1 times the first four natural frequencies (relative
// to the rotor's largest displacement there), converges to the full
// model's: measured 0.40, 0.013, 1.9e-4, 1.0e-5, 3.6e-6 at 4, 8, 12, 16 and
// 20 planar modes; each step of 4 modes from 4 to 16 shrinks it at least 10
// times (measured 30, 70 and 18 times), and 20 modes are within 1e-5
// (2.8x the measured 3.6e-6).
TEST(RotorReduction, AnisotropicBearingsConvergeToTheFullModel) {
  const core::FeRotor rotor = core::load_rotor_file(test::source_path("test/data/rotors/anisotropic_rig.yaml"));
  const core::RotorMatrices full = core::assemble(rotor);
  const int station = rotor.rub_station_node;
  const Eigen::MatrixXd full_compliance = full.K.inverse();
  const Eigen::Matrix2d want_static =
      full_compliance.block<2, 2>(core::dof_index(station, core::kDofX), core::dof_index(station, core::kDofX));
  for (int modes : {4, 6, 10}) {
    const core::ReducedRotor r = core::reduce_rotor(rotor, full, station, modes);
    const Eigen::Matrix2d got = Eigen::MatrixXd(r.matrices.K.inverse()).block<2, 2>(0, 0);
    EXPECT_LT((got - want_static).cwiseAbs().maxCoeff(), 1e-9 * want_static.cwiseAbs().maxCoeff()) << modes;
  }
  const auto modes_at_rest = core::modes(full, 0.0, 4);
  ASSERT_EQ(modes_at_rest.size(), 4u);
  auto worst_error = [&](const core::ReducedRotor& r) {
    double worst = 0.0;
    for (const auto& mode : modes_at_rest) {
      for (double ratio : {0.9, 1.1}) {
        const double w = ratio * mode.damped_frequency_rad_per_s;
        const Eigen::VectorXcd want = core::unbalance_response(full, rotor.unbalances, w);
        const Eigen::VectorXcd got = core::unbalance_response(r, rotor.unbalances, w);
        double largest = 0.0;
        for (int node = 0; node < rotor.nodes(); ++node) {
          for (auto dof : {core::kDofX, core::kDofY})
            largest = std::max(largest, std::abs(want(core::dof_index(node, dof))));
        }
        for (int node : {station, 0, rotor.nodes() - 1}) {
          for (auto dof : {core::kDofX, core::kDofY}) {
            const int i = core::dof_index(node, dof);
            worst = std::max(worst, std::abs(got(i) - want(i)) / largest);
          }
        }
      }
    }
    return worst;
  };
  double previous = worst_error(core::reduce_rotor(rotor, full, station, 4));
  for (int modes : {8, 12, 16}) {
    const double error = worst_error(core::reduce_rotor(rotor, full, station, modes));
    EXPECT_LT(error, previous / 10.0) << modes;
    previous = error;
  }
  EXPECT_LT(worst_error(core::reduce_rotor(rotor, full, station, 20)), 1e-5);
}

// One basis built for the most modes reduces to every smaller count exactly
// as that count's own reduction does (bitwise: the shapes of n planar modes
// are the first n of a larger count's), on the anisotropic rig and on the
// cross-coupled seal rotor, so rotor_planar_modes auto and the truncation
// study may build it once; a count above the one built for is refused.
TEST(RotorReduction, OneBasisReducesToEveryCountAsItsOwnReductionDoes) {
  for (const std::string path : {"test/data/rotors/anisotropic_rig.yaml", "config/rotors/seal_rub.yaml"}) {
    const core::FeRotor rotor = core::load_rotor_file(test::source_path(path));
    const core::RotorMatrices full = core::assemble(rotor);
    const int most = core::max_planar_modes(rotor);
    const core::RotorReduction reduction(rotor, full, rotor.rub_station_node, most);
    EXPECT_EQ(reduction.most_planar_modes(), most);
    for (int n : {1, 2, 3, 8, most - 1, most}) {
      const core::ReducedRotor own = core::reduce_rotor(rotor, full, rotor.rub_station_node, n);
      const core::ReducedRotor shared = reduction.reduce(n);
      ASSERT_EQ(shared.planar_modes, n) << path;
      EXPECT_EQ(shared.expansion, own.expansion) << path << " at " << n;
      EXPECT_EQ(shared.matrices.M, own.matrices.M) << path << " at " << n;
      EXPECT_EQ(shared.node_z_m, own.node_z_m) << path << " at " << n;
      EXPECT_EQ(shared.matrices.K, own.matrices.K) << path << " at " << n;
      EXPECT_EQ(shared.matrices.C, own.matrices.C) << path << " at " << n;
      EXPECT_EQ(shared.matrices.G, own.matrices.G) << path << " at " << n;
      EXPECT_EQ(shared.station_mass_kg, own.station_mass_kg) << path << " at " << n;
      EXPECT_EQ(shared.unit_weight_kg, own.unit_weight_kg) << path << " at " << n;
    }
    const core::RotorReduction few(rotor, full, rotor.rub_station_node, 4);
    try {
      few.reduce(5);
      ADD_FAILURE() << "5 planar modes from a reduction built for 4";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("5 is out of range; accepted: 1 to 4"), std::string::npos) << e.what();
    }
  }
}
