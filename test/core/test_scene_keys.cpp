#include <gtest/gtest.h>

#include <fstream>

#include "range_violation.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/simulation.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

using namespace rotor_rub;
using core::SceneError;

namespace {

std::string error_of(const std::map<std::string, std::string>& values) {
  try {
    core::scene_from_values(values);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(SceneKeys, PaperSceneLoadsWithTable1Values) {
  const core::Scene s = test::paper_scene();
  EXPECT_EQ(s.model.rotor_mass_kg, 0.418);
  EXPECT_EQ(s.model.stator_stiffness_N_per_m, 38166.0);
  EXPECT_EQ(s.model.clearance_m, 2.0e-3);
  EXPECT_EQ(s.model.contact_stiffness_N_per_m, 1.0e9);
  EXPECT_EQ(s.speed.acceleration_rad_per_s2, 70.0);
  EXPECT_EQ(s.end_time_s, 4.0);
}

// Every key, given a value of the wrong kind, is named in the error with the
// value and its accepted range.
TEST(SceneKeys, EveryKeyRejectsABadValueByName) {
  for (const auto& k : core::scene_keys()) {
    for (const std::string bad : {"nan", "banana", "-1e308", "1e308x"}) {
      const std::string msg = error_of({{k.key, bad}});
      if (msg.empty()) {
        // Some keys accept a negative huge number (initial_angle_rad); all
        // must reject the other three.
        EXPECT_EQ(bad, "-1e308") << k.key;
        continue;
      }
      EXPECT_NE(msg.find("'" + k.key + "'"), std::string::npos) << msg;
      EXPECT_NE(msg.find(bad), std::string::npos) << msg;
      EXPECT_NE(msg.find("accepted"), std::string::npos) << msg;
    }
  }
}

// Every key with a bounded range, given a value just outside it, names the
// key, the value and the accepted range.
TEST(SceneKeys, EveryKeyRejectsAValueOutsideItsRange) {
  int bounded = 0;
  for (const auto& k : core::scene_keys()) {
    const std::string bad = test::outside_range(k.accepted);
    if (bad.empty()) continue;
    ++bounded;
    const std::string msg = error_of({{k.key, bad}});
    EXPECT_NE(msg.find("'" + k.key + "'"), std::string::npos) << k.key << " = " << bad << ": " << msg;
    EXPECT_NE(msg.find("accepted: " + k.accepted), std::string::npos) << k.key << " = " << bad << ": " << msg;
  }
  EXPECT_GT(bounded, 25);  // all numeric keys but the unbounded initial_angle_rad
}

TEST(SceneKeys, OutOfRangeNamesTheRange) {
  const std::string msg = error_of({{"clearance_m", "-0.002"}});
  EXPECT_NE(msg.find("clearance_m"), std::string::npos);
  EXPECT_NE(msg.find("(0, inf)"), std::string::npos) << msg;
  EXPECT_NE(error_of({{"restitution", "1.5"}}).find("[0, 1]"), std::string::npos);
  EXPECT_NE(error_of({{"method", "euler"}}).find("penalty switching iteration"), std::string::npos);
  EXPECT_NE(error_of({{"max_steps", "2.5"}}).find("value 2.5 is not an integer; accepted: integer in"),
            std::string::npos)
      << error_of({{"max_steps", "2.5"}});
  EXPECT_NE(error_of({{"max_steps", "0"}}).find("value 0 is out of range"), std::string::npos);
}

TEST(SceneKeys, UnknownKeySuggestsTheNearest) {
  const std::string msg = error_of({{"clearence_m", "0.002"}});
  EXPECT_NE(msg.find("unknown scene key 'clearence_m'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("did you mean 'clearance_m'"), std::string::npos) << msg;
}

// What is wrong is typed, for callers that act on it: an unknown key, and a
// value the rotor file cannot take, with the key each concerns.
TEST(SceneKeys, ErrorsSayTheirKeyAndKind) {
  auto error = [](const std::map<std::string, std::string>& values) -> SceneError {
    try {
      core::scene_from_values(values);
    } catch (const SceneError& e) {
      return e;
    }
    return SceneError("none");
  };
  const SceneError unknown = error({{"clearence_m", "0.002"}});
  EXPECT_EQ(unknown.kind(), SceneError::Kind::kUnknownKey);
  EXPECT_EQ(unknown.key(), "clearence_m");
  const SceneError modes =
      error({{"rotor_file", test::source_path("config/rotors/seal_rub.yaml")}, {"rotor_planar_modes", "99"}});
  EXPECT_EQ(modes.kind(), SceneError::Kind::kInvalid);
  EXPECT_EQ(modes.key(), "rotor_planar_modes");
  EXPECT_NE(std::string(modes.what()).find("scene key 'rotor_planar_modes': value 99 is out of range; accepted for"),
            std::string::npos)
      << modes.what();
}

TEST(SceneKeys, CrossKeyRules) {
  EXPECT_EQ(error_of({{"integrator", "rosenbrock4"}, {"method", "switching"}}), "");  // in free flight
  EXPECT_EQ(error_of({{"integrator", "rosenbrock4"}, {"method", "penalty"}}), "");
  EXPECT_EQ(error_of({{"integrator", "rosenbrock4"}, {"method", "iteration"}}), "");  // in free flight
  EXPECT_EQ(error_of({{"integrator", "dop853_rosenbrock4"}, {"method", "switching"}}), "");
  EXPECT_EQ(error_of({{"integrator", "dop853_rosenbrock4"}, {"method", "iteration"}}), "");
  EXPECT_NE(error_of({{"integrator", "dop853_rosenbrock4"}, {"method", "penalty"}})
                .find("'dop853_rosenbrock4' is accepted with methods 'switching' and 'iteration' only"),
            std::string::npos);
  EXPECT_NE(error_of({{"integrator", "rk4"}, {"method", "iteration"}})
                .find("'rk4' is accepted with method 'penalty' only; accepted for method 'iteration': "
                      "auto, dop853_rosenbrock4, dop853, dopri5, rosenbrock4"),
            std::string::npos);
  // The high-order integrators: rkf78 the switching method's, dop853 the
  // switching and iteration methods' (the penalty contact is stiff; the
  // iteration method let a graze through with rkf78).
  EXPECT_NE(error_of({{"integrator", "rkf78"}, {"method", "penalty"}})
                .find("'rkf78' is accepted with method 'switching' only; accepted for method 'penalty': "
                      "auto, rosenbrock4, dopri5, rk4"),
            std::string::npos);
  EXPECT_NE(error_of({{"integrator", "rkf78"}, {"method", "iteration"}})
                .find("accepted for method 'iteration': auto, dop853_rosenbrock4, dop853, dopri5, rosenbrock4"),
            std::string::npos);
  EXPECT_EQ(error_of({{"integrator", "rkf78"}, {"method", "switching"}}), "");
  EXPECT_EQ(error_of({{"integrator", "dop853"}, {"method", "switching"}}), "");
  EXPECT_EQ(error_of({{"integrator", "dop853"}, {"method", "iteration"}}), "");
  EXPECT_NE(error_of({{"integrator", "dop853"}, {"method", "penalty"}})
                .find("'dop853' is accepted with methods 'switching' and 'iteration' only; accepted for method "
                      "'penalty': auto, rosenbrock4, dopri5, rk4"),
            std::string::npos);
  // auto: every method's registry choice.
  for (const char* m : {"penalty", "switching", "iteration"}) {
    EXPECT_EQ(error_of({{"integrator", "auto"}, {"method", m}}), "") << m;
  }
  EXPECT_NE(error_of({{"target_speed_rad_per_s", "3000"}}).find("max_speed_rad_per_s"), std::string::npos);
  // A constant speed needs no dummy acceleration; a ramp with none is refused by name.
  EXPECT_EQ(
      error_of(
          {{"acceleration_rad_per_s2", "0"}, {"initial_speed_rad_per_s", "300"}, {"target_speed_rad_per_s", "300"}}),
      "");
  EXPECT_NE(
      error_of(
          {{"acceleration_rad_per_s2", "0"}, {"initial_speed_rad_per_s", "300"}, {"target_speed_rad_per_s", "330"}})
          .find("scene key 'acceleration_rad_per_s2': value 0 holds the speed, but target_speed_rad_per_s = "
                "330 is not initial_speed_rad_per_s = 300; accepted: (0, inf) for a ramp to the target, 0 "
                "with the two speeds equal"),
      std::string::npos)
      << error_of(
             {{"acceleration_rad_per_s2", "0"}, {"initial_speed_rad_per_s", "300"}, {"target_speed_rad_per_s", "330"}});
}

TEST(SceneFile, RejectsNestedYamlAndDuplicates) {
  const std::string path = rotor_rub::test::tmp() + "rotor_rub_test_nested.yaml";
  {
    std::ofstream f(path);
    f << "rotor:\n  mass_kg: 1.0\n";
  }
  EXPECT_THROW(core::load_scene(path), SceneError);
  {
    std::ofstream f(path);
    f << "clearance_m: 1e-3\nclearance_m: 2e-3\n";
  }
  EXPECT_THROW(core::load_scene(path), SceneError);
  EXPECT_THROW(core::load_scene("/nonexistent/scene.yaml"), SceneError);
}

TEST(SceneFile, OverridesApplyAfterTheFile) {
  const core::Scene s = core::load_scene(test::source_path("config/paper_runup.yaml"), {{"method", "penalty"}});
  EXPECT_EQ(s.solver.method, core::Method::kPenalty);
}

// config/scene_template.yaml documents every key and loads as a scene.
TEST(SceneFile, TemplateDocumentsEveryKey) {
  const auto values = core::read_scene_values(test::source_path("config/scene_template.yaml"));
  for (const auto& k : core::scene_keys()) EXPECT_EQ(values.count(k.key), 1u) << k.key << " missing from the template";
  EXPECT_EQ(values.size(), core::scene_keys().size());
  EXPECT_NO_THROW(core::scene_from_values(values));
}

// A constant speed (acceleration_rad_per_s2 0, the target the initial
// speed) holds its speed, and the spin angle is w t, on every sample of a
// run (the paper's rotor at 300 rad/s, far above its 77 rad/s critical
// speed; 1e-12: the angle's rounding over 0.2 s).
TEST(SceneKeys, AConstantSpeedSceneHoldsItsSpeed) {
  core::Scene s = core::scene_from_values({{"acceleration_rad_per_s2", "0"},
                                           {"initial_speed_rad_per_s", "300"},
                                           {"target_speed_rad_per_s", "300"},
                                           {"end_time_s", "0.2"}});
  struct Speeds : core::SimulationObserver {
    std::vector<core::Sample> samples;
    void on_sample(const core::Sample& x) override { samples.push_back(x); }
  } obs;
  const core::RunResult r = core::run_scene(s, obs);
  ASSERT_FALSE(r.failure) << r.failure->message;
  ASSERT_EQ(obs.samples.size(), 201u);
  for (const auto& x : obs.samples) {
    EXPECT_EQ(x.drive.speed_rad_per_s, 300.0) << x.t_s;
    EXPECT_NEAR(x.drive.angle_rad, 300.0 * x.t_s, 1e-12) << x.t_s;
  }
}
