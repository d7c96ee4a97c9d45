// Gravity on a flexible rotor (a horizontal machine): the weight of every
// mass, the consistent load -g M t_y of the full FE model projected onto the
// reduced coordinates (ReducedRotor::unit_weight_kg). Closed forms: the
// static sag K q = f_g, and the rotor resting on its seal, where the seal
// carries the share of the weight that holds the station at the clearance.
// test/data/rotors/horizontal_seal.yaml has 14 planar modes; kept all, the
// reduction is the full model.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/rotor_reduction.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

constexpr double kGravity_m_per_s2 = 9.81;
constexpr int kPlanarModes = 4;  // the runs' (cheap: explicit steps are bound by the highest mode kept)

struct HorizontalRotor {
  core::FeRotor rotor = core::load_rotor_file(test::source_path("test/data/rotors/horizontal_seal.yaml"));
  core::RotorMatrices full = core::assemble(rotor);
  int station = rotor.rub_station_node;

  // The full model's static sag under gravity: K q = -g M t_y.
  Eigen::VectorXd full_sag() const {
    Eigen::VectorXd rigid_y = Eigen::VectorXd::Zero(full.M.rows());
    for (int node = 0; node < rotor.nodes(); ++node) rigid_y(core::dof_index(node, core::kDofY)) = 1.0;
    return full.K.ldlt().solve(-kGravity_m_per_s2 * (full.M * rigid_y));
  }
  core::ReducedRotor reduced(int planar_modes) const { return core::reduce_rotor(rotor, full, station, planar_modes); }
};

// The reduced model's own static state under gravity, q = K_r^-1 f_r, and
// its compliance at the station's y, (K_r^-1)_yy [m/N].
struct ReducedStatics {
  Eigen::VectorXd sag;
  double station_compliance_m_per_N;
};
ReducedStatics reduced_statics(const core::ReducedRotor& r) {
  const Eigen::MatrixXd flexibility = r.matrices.K.inverse();
  return {flexibility * (-kGravity_m_per_s2 * r.unit_weight_kg),
          flexibility(core::ReducedRotor::kStationY, core::ReducedRotor::kStationY)};
}

core::Scene horizontal_scene(const test::Solver& solver, double clearance_m) {
  core::Scene s = core::load_scene(test::source_path("config/seal_rub_runup.yaml"));
  s.rotor.file = test::source_path("test/data/rotors/horizontal_seal.yaml");
  s.rotor.planar_modes = kPlanarModes;
  s.model.gravity_m_per_s2 = kGravity_m_per_s2;
  s.model.clearance_m = clearance_m;
  s.model.friction_coefficient = 0.3;
  s.model.restitution = 0.0;
  s.speed.initial_speed_rad_per_s = s.speed.target_speed_rad_per_s = 0.0;
  s.solver.method = solver.method;
  s.solver.integrator = solver.integrator;
  s.solver.rtol = 1e-10;
  s.solver.atol = 1e-14;
  s.end_time_s = 1.5;
  s.output_rate_hz = 100.0;
  return s;
}

}  // namespace

// The projection: with every planar mode kept the reduced sag is the full
// model's at every node (1e-9 of the largest: the inverse's rounding); with
// four it is within 1 % at the station (a smooth load, carried mostly by
// the station's constraint modes and the first shaft modes).
TEST(FlexibleRotorGravity, ReducedSagIsTheFullModels) {
  const HorizontalRotor h;
  const Eigen::VectorXd full = h.full_sag();
  const int station_y = core::dof_index(h.station, core::kDofY);
  ASSERT_LT(full(station_y), -1e-5);  // it sags by tens of micrometres
  const core::ReducedRotor all = h.reduced(core::max_planar_modes(h.rotor));
  const Eigen::VectorXd expanded = all.expansion * reduced_statics(all).sag;
  EXPECT_LT((expanded - full).cwiseAbs().maxCoeff(), 1e-9 * full.cwiseAbs().maxCoeff());
  const core::ReducedRotor few = h.reduced(kPlanarModes);
  EXPECT_NEAR(reduced_statics(few).sag(core::ReducedRotor::kStationY), full(station_y),
              1e-2 * std::abs(full(station_y)));
}

// Released at rest with a wide clearance, the rotor settles onto its static
// sag: the station at the reduced model's K_r^-1 f_r within 1e-9 of it
// after 1.5 s (the dampers at the seal and the bearings have taken the
// transient away: the last two samples, 10 ms apart, agree to 1e-13 of the
// sag, measured), and nothing sideways.
TEST(FlexibleRotorGravity, SettlesOntoItsStaticSag) {
  const HorizontalRotor h;
  const ReducedStatics statics = reduced_statics(h.reduced(kPlanarModes));
  const double sag_m = statics.sag(core::ReducedRotor::kStationY);
  for (const test::Solver& solver : test::all_solvers()) {
    SCOPED_TRACE(solver.name());
    core::Scene s = horizontal_scene(solver, 1e-3);
    const test::Run r = test::run(s);
    ASSERT_FALSE(r.result.failure) << r.result.failure->message;
    EXPECT_TRUE(r.out.events.empty());
    const core::Sample& end = r.out.samples.back();
    EXPECT_NEAR(end.kin.rotor_pos.y(), sag_m, 1e-9 * std::abs(sag_m));
    EXPECT_LT(std::abs(end.kin.rotor_pos.x()), 1e-12 * std::abs(sag_m));
  }
}

// With the clearance below the sag the rotor comes to rest on the seal's
// bottom: the station held at (0, -C), the seal carrying
//   N = (-C - a) / b,   a = the free sag there, b = (K_r^-1)_yy,
// (the station's y displaced from a by b N), and the penalty method's spring
// compressed by N / k_c: N = (-C - a) / (b + 1 / k_c). Within 1e-6 of N
// after 1.5 s (the rigid methods' impact is plastic; the rest is the
// decay of the modes with the station held).
TEST(FlexibleRotorGravity, RestsOnTheSealCarryingItsShareOfTheWeight) {
  const HorizontalRotor h;
  const ReducedStatics statics = reduced_statics(h.reduced(kPlanarModes));
  const double a = statics.sag(core::ReducedRotor::kStationY), b = statics.station_compliance_m_per_N;
  const double clearance_m = 0.5 * std::abs(a);
  for (const test::Solver& solver : test::all_solvers()) {
    SCOPED_TRACE(solver.name());
    const core::Scene s = horizontal_scene(solver, clearance_m);
    const bool penalty = solver.method == core::Method::kPenalty;
    const double want_N = (-clearance_m - a) / (b + (penalty ? 1.0 / s.model.contact_stiffness_N_per_m : 0.0));
    ASSERT_GT(want_N, 0.0);
    const test::Run r = test::run(s);
    ASSERT_FALSE(r.result.failure) << r.result.failure->message;
    const core::Sample& end = r.out.samples.back();
    EXPECT_TRUE(end.in_contact);
    EXPECT_NEAR(end.normal_force_N, want_N, 1e-6 * want_N);
    EXPECT_NEAR(end.kin.rotor_pos.y(), -clearance_m - (penalty ? want_N / s.model.contact_stiffness_N_per_m : 0.0),
                1e-6 * clearance_m);
    EXPECT_LT(std::abs(end.contact_force_on_rotor_N.x()), 1e-6 * want_N);  // straight up: no friction at rest
  }
}
