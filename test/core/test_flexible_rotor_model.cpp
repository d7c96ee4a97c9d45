// The reduced flexible rotor's free forces (flexible_rotor_model.hpp): at
// rest in its coordinates they are the unbalances' forces of the full FE
// model projected (spin angle, speed and acceleration as the Jeffcott's
// law), and integrated in free flight from the closed-form steady state they
// stay on it (the unbalance response), so the stiffness, damping and
// gyroscopic terms are the ones the modal analysis uses.
#include <gtest/gtest.h>

#include <boost/numeric/odeint.hpp>
#include <boost/numeric/odeint/external/eigen/eigen.hpp>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

namespace {

struct SealRotor {
  core::FeRotor rotor = core::load_rotor_file(test::source_path("config/rotors/seal_rub.yaml"));
  core::RotorMatrices full = core::assemble(rotor);
  core::ReducedRotor reduced = core::reduce_rotor(rotor, full, rotor.rub_station_node, 4);
};

}  // namespace

// q = 0, q' = 0: the forces are the unbalances' alone, m e (w^2 (cos, sin) +
// A (sin, -cos))(phi + beta) at each node, projected: E^T f. Roundoff: 1e-12
// of the largest.
TEST(FlexibleRotorModel, UnbalanceForcesAreTheFullModelsProjected) {
  const SealRotor s;
  const core::FlexibleRotorModel model(s.reduced, s.rotor.unbalances);
  ASSERT_EQ(model.modal_size(), 6);
  const core::ModalState zero = core::ModalState::Zero(2 * model.modal_size());
  for (const auto& [phi, w, a] : {std::tuple{0.0, 300.0, 0.0}, {1.1, 250.0, 70.0}, {4.0, 10.0, -500.0}}) {
    core::ModalVector modal_acc(model.modal_size());
    const core::Vec2 station_N = model.free_loads(core::Vec2::Zero(), core::Vec2::Zero(), zero,
                                                  core::Vec2(std::cos(phi), std::sin(phi)), w, a, modal_acc);
    Eigen::VectorXd f = Eigen::VectorXd::Zero(s.full.M.rows());
    for (const auto& u : s.rotor.unbalances) {
      const double angle = phi + u.phase_rad;
      f(core::dof_index(u.node, core::kDofX)) += u.me_kg_m * (w * w * std::cos(angle) + a * std::sin(angle));
      f(core::dof_index(u.node, core::kDofY)) += u.me_kg_m * (w * w * std::sin(angle) - a * std::cos(angle));
    }
    const Eigen::VectorXd want = s.reduced.expansion.transpose() * f;
    const double scale = want.cwiseAbs().maxCoeff();
    EXPECT_LT((station_N - want.head<2>()).cwiseAbs().maxCoeff(), 1e-12 * scale) << phi;
    EXPECT_LT((modal_acc - want.tail(model.modal_size())).cwiseAbs().maxCoeff(), 1e-12 * scale) << phi;
  }
}

// Free flight at a constant 300 rad/s (above the first critical speed)
// from the steady state of the reduced model's unbalance response: 0.05 s
// later (15 turns) the motion is still Re(Q e^{i w t}). A force with a
// wrong sign or a missing gyroscopic term starts a transient of the order
// of the response itself; dopri5 at rtol 1e-10 keeps 1e-8 of it.
TEST(FlexibleRotorModel, FreeFlightStaysOnTheUnbalanceResponse) {
  const SealRotor s;
  const core::FlexibleRotorModel model(s.reduced, s.rotor.unbalances);
  const double w = 300.0, m_st = model.station_mass_kg();
  const int n = s.reduced.size();
  // Reduced response: E^T-projected forces, solved in the reduced matrices.
  const Eigen::VectorXcd q_full = core::unbalance_response(s.reduced, s.rotor.unbalances, w);
  // Back to reduced coordinates: the expansion has full column rank; least squares is exact here.
  const Eigen::VectorXcd q = s.reduced.expansion.cast<std::complex<double>>().colPivHouseholderQr().solve(q_full);
  using State = Eigen::VectorXd;
  State x(2 * n);
  const std::complex<double> i(0.0, 1.0);
  for (int k = 0; k < n; ++k) {
    x(k) = q(k).real();
    x(n + k) = (i * w * q(k)).real();
  }
  auto rhs = [&](const State& y, State& dy, double t) {
    core::ModalState modal(2 * (n - 2));
    modal << y.segment(2, n - 2), y.tail(n - 2);
    core::ModalVector modal_acc(n - 2);
    const core::Vec2 station_N = model.free_loads(y.head<2>(), y.segment<2>(n), modal,
                                                  core::Vec2(std::cos(w * t), std::sin(w * t)), w, 0.0, modal_acc);
    dy.head(n) = y.tail(n);
    dy.segment<2>(n) = station_N / m_st;
    dy.tail(n - 2) = modal_acc;
  };
  namespace odeint = boost::numeric::odeint;
  using Stepper = odeint::runge_kutta_dopri5<State, double, State, double, odeint::vector_space_algebra>;
  const double t_end = 0.05;
  odeint::integrate_adaptive(odeint::make_controlled<Stepper>(1e-14, 1e-10), rhs, x, 0.0, t_end, 1e-5);
  const double scale = q.cwiseAbs().maxCoeff();
  for (int k = 0; k < n; ++k) {
    const double want = (q(k) * std::exp(i * w * t_end)).real();
    EXPECT_NEAR(x(k), want, 1e-8 * scale) << k;
  }
}

// The rates (the switching method's jerk) are the forces' time derivatives
// along a motion: against a central difference of free_loads along q(t) = q0
// + q0' t + q0'' t^2 / 2 under phi = phi0 + w t + A t^2 / 2, w(t) = w0 + A t.
// The difference's truncation error (h^2 / 6 of the third derivative,
// h = 1e-6 s) and rounding (1e-16 |f| / h) are both below 1e-7 of the rate.
TEST(FlexibleRotorModel, RatesAreTheForcesTimeDerivatives) {
  const SealRotor s;
  const core::FlexibleRotorModel model(s.reduced, s.rotor.unbalances);
  const int n = model.modal_size();
  Eigen::VectorXd q0(n + 2), v0(n + 2), a0(n + 2);
  for (int i = 0; i < n + 2; ++i) {
    q0(i) = 1e-4 * std::sin(1.0 + i);
    v0(i) = 3e-2 * std::cos(2.0 * i);
    a0(i) = 10.0 * std::sin(0.5 + 3.0 * i);
  }
  const double phi0 = 0.7, w0 = 260.0, A = 70.0, h = 1e-6;
  auto loads_at = [&](double t, Eigen::VectorXd& out) {
    const Eigen::VectorXd q = q0 + v0 * t + 0.5 * a0 * t * t, v = v0 + a0 * t;
    core::ModalState modal(2 * n);
    modal << q.tail(n), v.tail(n);
    const double phi = phi0 + w0 * t + 0.5 * A * t * t;
    core::ModalVector acc(n);
    out.resize(n + 2);
    out.head<2>() =
        model.free_loads(q.head<2>(), v.head<2>(), modal, core::Vec2(std::cos(phi), std::sin(phi)), w0 + A * t, A, acc);
    out.tail(n) = acc;
  };
  Eigen::VectorXd before, after;
  loads_at(-h, before);
  loads_at(h, after);
  const Eigen::VectorXd want = (after - before) / (2.0 * h);
  core::ModalState rates(2 * n);
  rates << v0.tail(n), a0.tail(n);
  core::ModalVector jerk(n);
  const core::Vec2 station_rate =
      model.free_load_rates(v0.head<2>(), a0.head<2>(), rates, core::Vec2(std::cos(phi0), std::sin(phi0)), w0, A, jerk);
  const double scale = want.cwiseAbs().maxCoeff();
  EXPECT_LT((station_rate - want.head<2>()).cwiseAbs().maxCoeff(), 1e-7 * scale);
  EXPECT_LT((jerk - want.tail(n)).cwiseAbs().maxCoeff(), 1e-7 * scale);
}

// The shaft's nodes (the node's shaft topic): every node's displacement is
// the expansion's x and y rows times q = [u; xi], the station's is u itself
// (Craig-Bampton keeps it physical) and the probe node's is what the probes
// read. Roundoff: 1e-12 of the largest displacement.
TEST(FlexibleRotorModel, NodeDisplacementsAreTheExpansion) {
  const SealRotor s;
  const core::FlexibleRotorModel model(s.reduced, s.rotor.unbalances, 0.05, 12);
  ASSERT_EQ(model.nodes(), 13);
  ASSERT_EQ(s.reduced.node_z_m.size(), 13u);
  EXPECT_NEAR(s.reduced.node_z_m.back(), 1.2, 1e-12);
  const core::Vec2 u(3e-6, -2e-6);
  core::ModalState modal(2 * model.modal_size());
  for (int i = 0; i < modal.size(); ++i) modal(i) = 1e-6 * std::sin(1.0 + i);
  std::vector<core::Vec2> nodes;
  model.node_displacements(u, modal, nodes);
  ASSERT_EQ(nodes.size(), 13u);
  Eigen::VectorXd q(model.modal_size() + 2);
  q << u, modal.head(model.modal_size());
  const Eigen::VectorXd full = s.reduced.expansion * q;
  const double scale = full.cwiseAbs().maxCoeff();
  for (int node = 0; node < 13; ++node) {
    const core::Vec2 want(full(core::dof_index(node, core::kDofX)), full(core::dof_index(node, core::kDofY)));
    EXPECT_LT((nodes[node] - want).norm(), 1e-12 * scale) << node;
  }
  EXPECT_LT((nodes[6] - u).norm(), 1e-12 * scale);
  EXPECT_LT((nodes[12] - model.probe_displacement(u, modal)).norm(), 1e-12 * scale);
}

// A run reads its rotor file once: the scene carries what was read
// (RotorSettings::loaded), so the run, its validation and a live change go
// on after the file is gone, while a scene asking for other settings reads
// the file again (here: fails, naming it).
TEST(FlexibleRotorModel, TheSceneCarriesItsRotor) {
  const std::string path = test::tmp() + "/carried_seal.yaml";
  {
    std::ifstream in(test::source_path("config/rotors/seal_rub.yaml"));
    std::ofstream(path) << in.rdbuf();
  }
  std::map<std::string, std::string> values = core::read_scene_values(test::source_path("config/seal_rub_runup.yaml"));
  values["rotor_file"] = path;
  values["end_time_s"] = "0.01";
  const core::Scene scene = core::scene_from_values(values);
  ASSERT_TRUE(scene.rotor.loaded);
  ASSERT_EQ(std::remove(path.c_str()), 0);
  core::Simulation sim(scene);
  EXPECT_EQ(sim.scene().rotor.loaded->model, scene.rotor.loaded->model);
  core::SimulationObserver none;
  sim.advance_to(0.005, none);
  sim.change_parameters({{"friction_coefficient", "0.2"}});
  sim.advance_to(0.01, none);
  EXPECT_FALSE(sim.failure());
  core::Scene other = scene;
  other.rotor.planar_modes = 4;
  try {
    core::Simulation again(other);
    ADD_FAILURE() << "a scene with other settings did not read the (removed) file";
  } catch (const core::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("scene key 'rotor_file'"), std::string::npos) << e.what();
  }
}
