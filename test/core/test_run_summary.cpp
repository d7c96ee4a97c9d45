// The runner's JSON summary: valid JSON whatever the scene path holds, and
// read back by the comparison tool to the same events and figures.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

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
    tools::write_summary_json(js, {odd_path, &scene, &recorder, sim.stats(), &sim.failure(), sim.time()});
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
