// The one YAML reading (yaml_values.hpp): a file means what rosparam makes of
// it. The expected texts below are PyYAML's (yaml.safe_load, which rosparam
// uses), checked with Debian's python3-yaml 6.0:
//   /usr/bin/python3 -c "import yaml; print(repr(yaml.safe_load('k: 010')['k']))"
#include <gtest/gtest.h>

#include <fstream>

#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/yaml_values.hpp"
#include "sweep_grid.hpp"
#include "temp_dir.hpp"
#include "test_support.hpp"

using namespace rotor_rub;
using core::SceneError;
using core::YamlError;

namespace {

std::string write(const std::string& name, const std::string& text) {
  const std::string path = rotor_rub::test::tmp() + "rotor_rub_yaml_" + name + ".yaml";
  std::ofstream(path) << text;
  return path;
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// Each plain scalar resolves as PyYAML's YAML 1.1 resolvers do, and gets the
// text the node builds from the typed rosparam value.
TEST(YamlValues, PlainScalarsResolveAsRosparamDoes) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"1.0e+3", "1000"},   // float
      {"1_000.0", "1000"},  // float with digit separators
      {"0.4e-3", "4e-04"},  // float (the shortest text of that double)
      {".5", "0.5"},        // float without a leading digit
      {"1.", "1"},          // float
      {"+.inf", "inf"},     // float, rejected later by every key as not finite
      {"0x10", "16"},       // int, hexadecimal
      {"010", "8"},         // int, octal in YAML 1.1
      {"0b101", "5"},       // int, binary
      {"1_000", "1000"},    // int with separators
      {"1:30", "90"},       // int, sexagesimal
      {"+12", "12"},        // int
      {"yes", "true"},      // bool
      {"Off", "false"},     // bool
      {"1e-6", "1e-6"},     // a string to YAML 1.1 (no dot): the key table parses the text
      {"1.0e6", "1.0e6"},   // a string to YAML 1.1 (exponent without sign)
      {"08", "08"},         // a string (not octal)
      {"switching", "switching"},
  };
  for (const auto& [scalar, expected] : cases) {
    EXPECT_EQ(core::rosparam_scalar_text(scalar, false, "here"), expected) << scalar;
  }
  // A quoted scalar is the string, whatever it looks like.
  EXPECT_EQ(core::rosparam_scalar_text("010", true, "here"), "010");
  EXPECT_EQ(core::rosparam_scalar_text("", true, "here"), "");
}

TEST(YamlValues, ValuesRosparamCannotPassAreErrorsNamingThePlace) {
  for (const std::string bad : {"~", "null", "", "3000000000", "-2147483649", "deg(90)", "rad(pi)", "0b_", "0x_"}) {
    const std::string msg = error_of([&] { core::rosparam_scalar_text(bad, false, "f.yaml:3:7"); });
    EXPECT_NE(msg.find("f.yaml:3:7"), std::string::npos) << bad << ": " << msg;
  }
  EXPECT_EQ(core::rosparam_scalar_text("2147483647", false, "x"), "2147483647");
  EXPECT_EQ(core::rosparam_scalar_text("-2147483648", false, "x"), "-2147483648");
}

// Valid YAML that the old line reader rejected: flow mappings, quoted
// numbers, anchors and aliases, a document marker.
TEST(YamlValues, SceneFilesMayUseAnyYaml) {
  const std::string path = write("flow", "---\n{rtol: 1.0e-4, method: 'penalty'}\n");
  const core::Scene flow = core::load_scene(path);
  EXPECT_EQ(flow.solver.rtol, 1.0e-4);
  EXPECT_EQ(flow.solver.method, core::Method::kPenalty);

  const std::string anchors = write("anchors",
                                    "rotor_damping_N_s_per_m: &c 2.5   # an anchor\n"
                                    "stator_damping_N_s_per_m: *c\n"
                                    "clearance_m: \"1.5e-3\"\n"
                                    "max_steps: 1_000_000\n");
  const core::Scene s = core::load_scene(anchors);
  EXPECT_EQ(s.model.rotor_damping_N_s_per_m, 2.5);
  EXPECT_EQ(s.model.stator_damping_N_s_per_m, 2.5);
  EXPECT_EQ(s.model.clearance_m, 1.5e-3);
  EXPECT_EQ(s.solver.max_steps, 1000000);
  // The core tags, as rosparam reads them.
  const core::Scene tagged = core::load_scene(write("tags", "end_time_s: !!float 0.5\nmax_steps: !!int 1000\n"));
  EXPECT_EQ(tagged.end_time_s, 0.5);
  EXPECT_EQ(tagged.solver.max_steps, 1000);
}

// The example: `rtol:1.0e-4` is no key to YAML (a plain scalar), so
// rosparam loads nothing for it; the runner must not read it as rtol either.
TEST(YamlValues, AKeyWithoutASpaceAfterTheColonIsAnError) {
  std::string msg = error_of([] { core::load_scene(write("nospace_alone", "rtol:1.0e-4\n")); });
  EXPECT_NE(msg.find("rtol:1.0e-4"), std::string::npos) << msg;
  EXPECT_NE(msg.find("space after the colon"), std::string::npos) << msg;
  msg = error_of([] { core::load_scene(write("nospace", "method: switching\nrtol:1.0e-4\n")); });
  EXPECT_NE(msg.find("rotor_rub_yaml_nospace.yaml:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("a space after its colon"), std::string::npos) << msg;
}

TEST(YamlValues, SceneFileErrorsNameFileLineAndKey) {
  std::string msg = error_of([] { core::load_scene(write("nested", "rotor:\n  mass_kg: 1.0\n")); });
  EXPECT_NE(msg.find("'rotor'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("mapping"), std::string::npos) << msg;
  msg = error_of([] { core::load_scene(write("twice", "clearance_m: 1e-3\nclearance_m: 2e-3\n")); });
  EXPECT_NE(msg.find("rotor_rub_yaml_twice.yaml:2:1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("given twice"), std::string::npos) << msg;
  msg = error_of([] { core::load_scene(write("list", "rtol: [1.0e-3, 1.0e-6]\n")); });
  EXPECT_NE(msg.find("'rtol'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("sweep grid"), std::string::npos) << msg;
  msg = error_of([] { core::load_scene(write("empty_value", "rtol:\n")); });
  EXPECT_NE(msg.find("has no value"), std::string::npos) << msg;
  msg = error_of([] { core::load_scene(write("bad_yaml", "rtol: [1.0e-3\n")); });
  EXPECT_NE(msg.find("not valid YAML"), std::string::npos) << msg;
  msg = error_of([] { core::load_scene(write("two_docs", "rtol: 1.0e-3\n---\nrtol: 1.0e-4\n")); });
  EXPECT_NE(msg.find("2 YAML documents"), std::string::npos) << msg;
  msg = error_of([] { core::load_scene("/nonexistent/scene.yaml"); });
  EXPECT_NE(msg.find("cannot be opened"), std::string::npos) << msg;
  // Every failure is a SceneError to the callers.
  EXPECT_THROW(core::load_scene(write("nested", "rotor:\n  mass_kg: 1.0\n")), SceneError);
}

// A bad value in the file is an error even where an override replaces it.
TEST(YamlValues, ABadFileValueFailsEvenWhenOverridden) {
  const std::string path = write("bad_rate", "output_rate_hz: abc\n");
  const std::string msg = error_of([&] { core::load_scene(path, {{"output_rate_hz", "1000"}}); });
  EXPECT_NE(msg.find("output_rate_hz"), std::string::npos) << msg;
  EXPECT_NE(msg.find("abc"), std::string::npos) << msg;
  EXPECT_NE(msg.find("rotor_rub_yaml_bad_rate.yaml:1:17"), std::string::npos) << msg;
}

// scene_values() is the scene exactly: it reads back to the same scene, key
// by key, doubles to the last bit.
TEST(YamlValues, SceneValuesReadBackToTheSameScene) {
  core::Scene s = test::paper_scene();
  s.model.eccentricity_m = 0.1 + 0.2;  // a double with no short decimal form
  s.solver.method = core::Method::kIteration;
  const auto values = core::scene_values(s);
  EXPECT_EQ(values.size(), core::scene_keys().size());
  const core::Scene back = core::scene_from_values(values);
  EXPECT_EQ(back.model.eccentricity_m, s.model.eccentricity_m);
  EXPECT_EQ(core::scene_values(back), values);
}

TEST(YamlValues, SweepGridsReadListsAndDocuments) {
  const std::string path = write("grid",
                                 "method: [switching, iteration]\n"
                                 "rtol:\n  - 1.0e-3\n  - 1e-6\n"
                                 "---\n"
                                 "# comments only\n"
                                 "---\n"
                                 "{method: penalty, contact_stiffness_N_per_m: [1.0e+8, 1.0e+9]}\n");
  const auto docs = tools::read_grid_file(path);
  ASSERT_EQ(docs.size(), 2u);  // the empty document is dropped
  ASSERT_EQ(docs[0].size(), 2u);
  EXPECT_EQ(docs[0][0].key, "method");  // file order: the last key varies fastest
  EXPECT_EQ(docs[0][1].values, (std::vector<std::string>{"0.001", "1e-6"}));
  EXPECT_EQ(docs[1][1].values, (std::vector<std::string>{"1e+08", "1e+09"}));
  EXPECT_EQ(tools::expand_grid(docs, {}).size(), 6u);
}

// A grid value the grid computes with is checked by name (was: "stod").
TEST(YamlValues, GridPseudoKeyArithmeticNamesTheBadValue) {
  const auto docs = tools::read_grid_file(write("grid_bad", "rtol: [abc]\natol_per_rtol: 1.0e-3\n"));
  const std::string msg = error_of([&] { tools::expand_grid(docs, {}); });
  EXPECT_NE(msg.find("'rtol'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'abc'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("accepted"), std::string::npos) << msg;
}

// Every scene and grid the project ships reads without error.
TEST(YamlValues, ShippedFilesRead) {
  for (const char* scene : {"config/paper_runup.yaml", "config/scene_template.yaml", "config/dry_whirl_rundown.yaml"}) {
    EXPECT_NO_THROW(core::load_scene(test::source_path(scene))) << scene;
  }
  for (const char* grid :
       {"config/sweeps/smoke.yaml", "config/sweeps/work_precision.yaml", "config/sweeps/paper_table2.yaml",
        "config/sweeps/parameter_study.yaml", "config/sweeps/transitions.yaml", "config/sweeps/loose_tolerance.yaml"}) {
    EXPECT_NO_THROW(tools::expand_grid(tools::read_grid_file(test::source_path(grid)), {})) << grid;
  }
}
