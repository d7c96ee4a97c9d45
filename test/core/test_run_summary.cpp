// The runner's JSON summary: valid JSON whatever the scene path holds, and
// read back by the comparison tool to the same events and figures.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/rotor_file.hpp"
#include "rotor_rub_sim/core/rotor_reduction.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "run_comparison.hpp"
#include "run_output.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

using namespace rotor_rub;

TEST(RunSummary, IsValidJsonAndReadsBackToTheSameRun) {
  core::Scene scene = test::paper_scene();
  scene.end_time_s = 1.5;  // through the first contacts (from about 1.13 s)
  scene.output_rate_hz = 200.0;
  tools::RunRecorder recorder(true);
  core::Simulation sim(scene);
  sim.advance_to(scene.end_time_s, recorder);
  ASSERT_FALSE(recorder.events.empty());

  // A path with a quote, a backslash and a newline was written unescaped.
  const std::string odd_path = rotor_rub::test::tmp() + "a \"quoted\" \\ path\n.yaml";
  const std::string csv = rotor_rub::test::tmp() + "rotor_rub_summary_test.csv",
                    json = rotor_rub::test::tmp() + "rotor_rub_summary_test.json";
  {
    std::ofstream os(csv);
    tools::write_csv(os, recorder.samples);
    std::ofstream js(json);
    tools::write_summary_json(
        js, {odd_path, &scene, &recorder, sim.stats(), &sim.failure(), sim.time(), sim.contact_point(), {}});
  }
  std::ifstream in(json);
  const nlohmann::json j = nlohmann::json::parse(in);  // throws on invalid JSON
  EXPECT_EQ(j.at("scene").get<std::string>(), odd_path);
  EXPECT_EQ(j.at("status").get<std::string>(), "ok");
  EXPECT_TRUE(j.at("last_liftoff_s").is_null() || j.at("last_liftoff_s").is_number());
  // The run ends at 1.5 s in the contact that began at the touchdown near
  // 1.11 s: sustained until the end, not unreported.
  const auto sustained = j.at("sustained_contact_s");
  ASSERT_TRUE(sustained.at(0).is_number());
  EXPECT_GT(sustained.at(0).get<double>(), 1.1);
  EXPECT_EQ(sustained.at(1).get<double>(), 1.5);
  // The whole scene, every key, reads back to the same scene.
  std::map<std::string, std::string> values = j.at("scene_values").get<std::map<std::string, std::string>>();
  EXPECT_EQ(core::scene_values(core::scene_from_values(values)), core::scene_values(scene));

  // What the contact meets: the paper's 0.418 kg rotor against its 0.86 kg
  // elastic stator, and k_c = 1e9 N/m on their effective mass (closed form;
  // 1e-12 relative: a few roundings).
  const double m_eff = 1.0 / (1.0 / 0.418 + 1.0 / 0.86);
  EXPECT_EQ(j.at("contact_point").at("mass_kg").get<double>(), 0.418);
  EXPECT_NEAR(j.at("contact_point").at("effective_mass_kg").get<double>(), m_eff, 1e-12 * m_eff);
  EXPECT_NEAR(j.at("contact_point").at("contact_mode_hz").get<double>(), std::sqrt(1e9 / m_eff) / (2.0 * M_PI),
              1e-12 * std::sqrt(1e9 / m_eff));
  // Its damper from the scene's restitution 0 (the penalty's floor 0.01):
  // 2 zeta sqrt(k_c m_eff), zeta = 4.81 (contact_law.md).
  const double zeta = core::contact_damping_ratio(0.0, core::penalty_restitution_floor(1e9));
  EXPECT_NEAR(zeta, 4.81, 0.01);
  EXPECT_NEAR(j.at("contact_point").at("contact_damping_N_s_per_m").get<double>(), 2.0 * zeta * std::sqrt(1e9 * m_eff),
              1e-12 * 2.0 * zeta * std::sqrt(1e9 * m_eff));

  const tools::RecordedRun back = tools::read_runner_csv(csv, json);
  EXPECT_EQ(back.method, "switching");
  EXPECT_EQ(back.steps, sim.stats().steps);
  EXPECT_EQ(back.rhs_evals, sim.stats().rhs_evals);
  ASSERT_EQ(back.events.size(), recorder.events.size());
  for (std::size_t i = 0; i < back.events.size(); ++i) {
    EXPECT_EQ(back.events[i].t_s, recorder.events[i].t_s) << i;  // 17 digits: exact
    EXPECT_EQ(back.events[i].kind, recorder.events[i].kind) << i;
    EXPECT_EQ(back.events[i].impulse_N_s, recorder.events[i].impulse_N_s) << i;
  }
  ASSERT_EQ(back.samples.size(), recorder.samples.size());
  EXPECT_EQ(back.samples.back().kin.rotor_pos, recorder.samples.back().kin.rotor_pos);
}

TEST(RunSummary, ABrokenSummaryIsAnErrorNamingTheFile) {
  const std::string csv = rotor_rub::test::tmp() + "rotor_rub_summary_bad.csv",
                    json = rotor_rub::test::tmp() + "rotor_rub_summary_bad.json";
  std::ofstream(csv)
      << "t,x_r,y_r,x_s,y_s,vx_r,vy_r,vx_s,vy_s,normal_force,friction_force,fx_contact,fy_contact,"
         "penetration,sliding_velocity,in_contact,spin_angle,speed,sticking,drive_torque,friction_torque\n";
  std::ofstream(json) << "{\"method\": \"switching\", \"events\": [";
  try {
    tools::read_runner_csv(csv, json);
    FAIL() << "a truncated summary was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(json), std::string::npos) << e.what();
  }
}

// A flexible rotor's contact point is its reduced model's station: the
// seal-rub example's 8 planar modes (m_st from the reduction itself) on a
// rigid seal, where the effective mass is the station's.
TEST(RunSummary, AFlexibleRotorsContactPointIsItsStation) {
  const core::Scene scene = core::load_scene(test::source_path("config/seal_rub_runup.yaml"));
  const core::Simulation sim(scene);
  const core::FeRotor rotor = core::load_rotor_file(test::source_path("config/rotors/seal_rub.yaml"));
  const double m_st = core::reduce_rotor(rotor, core::assemble(rotor), rotor.rub_station_node,
                                         static_cast<int>(scene.rotor.planar_modes))
                          .station_mass_kg;
  EXPECT_EQ(sim.contact_point().mass_kg, m_st);
  EXPECT_EQ(sim.contact_point().effective_mass_kg, m_st);
  EXPECT_EQ(sim.contact_point().contact_mode_rad_per_s, std::sqrt(scene.model.contact_stiffness_N_per_m / m_st));
}

// A ramp is one change to a user: the node answers it once, spanning its
// steps (live_changes.test), and rotor_rub_compare lists that answer as one
// entry with its span, the values before and after and its steps' count,
// beside a plain change and a one-step fault.
TEST(RunComparison, ARampIsOneChange) {
  tools::RecordedRun run;
  run.name = "ramp";
  for (int k = 0; k < 4; ++k) {
    core::Sample s;
    s.t_s = 0.5 * k;
    run.samples.push_back(s);
  }
  run.changes.push_back({0.5, 0.5, "clearance_m=0.0025", 1, "clearance_m=0.002", "clearance_m=0.0025", 1});
  run.changes.push_back({1.0, 1.004, "thermal_closure", 7, "clearance_m=0.0025", "clearance_m=0.002", 5});
  run.changes.push_back({1.2, 1.2, "blade_loss", 8, "eccentricity_m=0.0004 unbalance_phase_rad=0",
                         "eccentricity_m=0.0005 unbalance_phase_rad=0", 1});
  const tools::RunFigures f = tools::compare_run(run, run);
  EXPECT_EQ(f.live_changes, 3);
  EXPECT_EQ(f.first_change_s, 0.5);
  EXPECT_EQ(f.changes,
            "0.5 clearance_m=0.0025; 1..1.004 thermal_closure clearance_m=0.0025..clearance_m=0.002 (5 steps); "
            "1.2 blade_loss");
}
