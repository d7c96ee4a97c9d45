// Parity of the project's YAML reader with rosparam: every config/*.yaml (and
// fixtures in test/data with the YAML the old reader got wrong) loaded through
// `rosparam load` into a node's private namespace, read the way the node reads
// it, gives the same values and the same scene as the runner's reader.
#include <gtest/gtest.h>
#include <ros/ros.h>

#include <cstdlib>

#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/yaml_values.hpp"
#include "rotor_rub_sim/ros/conversions.hpp"
#include "rotor_rub_sim/ros/node_config.hpp"

using namespace rotor_rub;

namespace {

std::string source(const std::string& rel) { return std::string(ROTOR_RUB_SOURCE_DIR) + "/" + rel; }

// Both readers' texts mean the same value: as numbers when both are numbers
// (rosparam's floats come back as %.17g, the reader's as the shortest text),
// else as text.
bool same_value(const std::string& a, const std::string& b) {
  char* ea = nullptr;
  char* eb = nullptr;
  const double va = std::strtod(a.c_str(), &ea);
  const double vb = std::strtod(b.c_str(), &eb);
  if (!a.empty() && !b.empty() && *ea == '\0' && *eb == '\0') return va == vb;
  return a == b;
}

void check_parity(const std::string& file, int n) {
  SCOPED_TRACE(file);
  const std::string ns = "/yaml_parity_" + std::to_string(n) + "/node";
  ASSERT_EQ(std::system(("rosparam load '" + file + "' " + ns).c_str()), 0) << "rosparam load failed";
  ros::NodeHandle private_nh(ns);
  const std::map<std::string, std::string> via_rosparam = ros_node::private_params_as_text(private_nh);

  const auto docs = core::read_yaml_documents(file);
  ASSERT_EQ(docs.size(), 1u);
  std::map<std::string, std::string> via_reader;
  for (const auto& e : docs.front()) via_reader[e.key] = e.values.front();

  ASSERT_EQ(via_rosparam.size(), via_reader.size());
  for (const auto& [key, text] : via_reader) {
    ASSERT_EQ(via_rosparam.count(key), 1u) << key;
    EXPECT_TRUE(same_value(via_rosparam.at(key), text))
        << key << ": rosparam gives '" << via_rosparam.at(key) << "', the reader '" << text << "'";
  }
  // The node's scene from rosparam and the runner's from the file: equal
  // key by key (scene_values is exact).
  const ros_node::NodeSetup node = ros_node::node_setup_from_values(via_rosparam);
  const ros_node::NodeSetup reader = ros_node::node_setup_from_values(via_reader);
  EXPECT_EQ(core::scene_values(node.scene), core::scene_values(reader.scene));
  bool has_node_keys = false;
  for (const auto& [key, text] : via_reader) has_node_keys = has_node_keys || ros_node::is_node_key(key);
  if (!has_node_keys) {
    EXPECT_EQ(core::scene_values(node.scene), core::scene_values(core::load_scene(file)));
  }
}

}  // namespace

TEST(YamlParity, EveryShippedConfigAndFixture) {
  int n = 0;
  for (const char* file : {"config/paper_runup.yaml", "config/scene_template.yaml", "config/node_template.yaml",
                           "test/data/yaml_parity_anchors.yaml", "test/data/yaml_parity_flow.yaml"}) {
    check_parity(source(file), n++);
  }
}

// The fixtures really exercise YAML 1.1: the values the old reader got wrong.
TEST(YamlParity, FixturesMeanWhatYaml11Says) {
  const core::Scene s = core::load_scene(source("test/data/yaml_parity_anchors.yaml"));
  EXPECT_EQ(s.model.stator_mass_kg, 0.5);           // an alias
  EXPECT_EQ(s.model.clearance_m, 1.5e-3);           // a quoted number
  EXPECT_EQ(s.solver.rtol, 1e-6);                   // a string to YAML 1.1, a number to the key
  EXPECT_EQ(s.solver.max_steps, 1000000);           // digit separators
  EXPECT_EQ(s.output_rate_hz, 1000.0);              // hexadecimal
  EXPECT_EQ(s.solver.iteration_max_iterations, 8);  // octal
  EXPECT_EQ(s.solver.method, core::Method::kIteration);
  const core::Scene flow = core::load_scene(source("test/data/yaml_parity_flow.yaml"));
  EXPECT_EQ(flow.solver.method, core::Method::kPenalty);
  EXPECT_EQ(flow.model.friction_coefficient, 0.3);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_yaml_parity");
  ros::NodeHandle nh;
  return RUN_ALL_TESTS();
}
