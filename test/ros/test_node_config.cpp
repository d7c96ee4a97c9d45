// The node's parameter table, without a master: scene and node keys split,
// every bad value named with its accepted range, typos answered with the
// nearest key of either table.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "../core/range_violation.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/yaml_values.hpp"
#include "rotor_rub_sim/ros/node_config.hpp"

namespace rotor_rub::ros_node {
namespace {

std::string error_of(const std::map<std::string, std::string>& values) {
  try {
    node_setup_from_values(values);
  } catch (const core::SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(NodeConfig, SplitsSceneAndNodeKeys) {
  const NodeSetup s = node_setup_from_values({{"method", "iteration"},
                                              {"rtol", "1e-5"},
                                              {"real_time_factor", "0"},
                                              {"end_action", "continue"},
                                              {"start_paused", "true"},
                                              {"record_bag", "/tmp/x.bag"},
                                              {"orbit_trail_samples", "10"}});
  EXPECT_EQ(s.scene.solver.method, core::Method::kIteration);
  EXPECT_EQ(s.scene.solver.rtol, 1e-5);
  EXPECT_EQ(s.config.real_time_factor, 0.0);
  EXPECT_EQ(s.config.end_action, EndAction::kContinue);
  EXPECT_TRUE(s.config.start_paused);
  EXPECT_EQ(s.config.record_bag, "/tmp/x.bag");
  EXPECT_EQ(s.config.orbit_trail_samples, 10);
}

TEST(NodeConfig, DefaultsAreTheDocumentedOnes) {
  const NodeSetup s = node_setup_from_values({});
  const NodeConfig defaults;
  EXPECT_EQ(s.config.real_time_factor, defaults.real_time_factor);
  for (const auto& k : node_keys()) {
    EXPECT_FALSE(k.description.empty()) << k.key;
    EXPECT_FALSE(k.accepted.empty()) << k.key;
    EXPECT_TRUE(is_node_key(k.key));
    // No key is in both tables: a value must have one meaning.
    for (const auto& sk : core::scene_keys()) EXPECT_NE(sk.key, k.key);
  }
}

TEST(NodeConfig, BadValuesNameTheKeyAndTheRange) {
  EXPECT_NE(error_of({{"real_time_factor", "-1"}}).find("'real_time_factor': value -1 is out of range; accepted: [0,"),
            std::string::npos);
  EXPECT_NE(error_of({{"real_time_factor", "fast"}}).find("not a finite number"), std::string::npos);
  EXPECT_NE(error_of({{"real_time_factor", "nan"}}).find("not a finite number"), std::string::npos);
  EXPECT_NE(error_of({{"end_action", "stop"}}).find("accepted: exit | continue | pause"), std::string::npos);
  EXPECT_NE(error_of({{"start_paused", "maybe"}}).find("accepted: true | false"), std::string::npos);
  EXPECT_NE(error_of({{"orbit_trail_samples", "2.5"}}).find("integer in [2, "), std::string::npos);
  EXPECT_NE(error_of({{"frame_id", ""}}).find("'frame_id'"), std::string::npos);
  // The lockstep period must fall on the output grid (1 kHz here).
  EXPECT_NE(error_of({{"lockstep_period_s", "0.0105"}}).find("whole multiple of the output period"), std::string::npos);
  EXPECT_EQ(error_of({{"lockstep_period_s", "0.01"}}), "");
  EXPECT_EQ(error_of({{"lockstep_period_s", "0.005"}, {"output_rate_hz", "2000"}}), "");
  // Scene keys keep the scene's own messages.
  EXPECT_NE(error_of({{"rtol", "-1"}}).find("'rtol': value -1 is out of range"), std::string::npos);
}

// Every node key: a value of the wrong kind and, where the range is bounded,
// one just outside it, each named with the key and the accepted range.
TEST(NodeConfig, EveryKeyRejectsBadValuesByName) {
  int bounded = 0;
  for (const auto& k : node_keys()) {
    std::vector<std::string> bad = {"banana"};
    if (k.key == "record_bag") continue;  // any path is a value; an unwritable one fails at open (node test)
    if (k.key == "frame_id") bad = {""};
    const std::string outside = test::outside_range(k.accepted);
    if (!outside.empty()) {
      bad.push_back(outside);
      ++bounded;
    }
    for (const auto& v : bad) {
      const std::string msg = error_of({{k.key, v}});
      EXPECT_NE(msg.find("'" + k.key + "'"), std::string::npos) << k.key << " = '" << v << "': " << msg;
      EXPECT_NE(msg.find("accepted"), std::string::npos) << k.key << " = '" << v << "': " << msg;
    }
  }
  EXPECT_GT(bounded, 10);
}

TEST(NodeConfig, UnknownKeysSuggestTheNearestOfBothTables) {
  EXPECT_NE(error_of({{"rtoll", "1e-6"}}).find("did you mean 'rtol'?"), std::string::npos);
  EXPECT_NE(error_of({{"real_time_factr", "1"}}).find("did you mean 'real_time_factor'?"), std::string::npos);
  EXPECT_NE(error_of({{"zzzzzzzzzzzz", "1"}}).find("unknown parameter 'zzzzzzzzzzzz'"), std::string::npos);
  // Typed: the node's start-up tells a leftover parameter by its kind, not its text.
  try {
    node_setup_from_values({{"zzzzzzzzzzzz", "1"}});
    ADD_FAILURE() << "accepted an unknown parameter";
  } catch (const core::SceneError& e) {
    EXPECT_EQ(e.kind(), core::SceneError::Kind::kUnknownKey);
    EXPECT_EQ(e.key(), "zzzzzzzzzzzz");
  }
}

}  // namespace
}  // namespace rotor_rub::ros_node

namespace rotor_rub::ros_node {
namespace {

// config/node_template.yaml documents every node key with its default (it is
// generated from the key table; this catches a key added without
// regenerating it) and loads as the node's parameters, giving the defaults.
TEST(NodeConfig, TemplateListsEveryKeyWithItsDefault) {
  // Read as rosparam reads it (the project's one YAML reader).
  const auto docs = core::read_yaml_documents(std::string(ROTOR_RUB_SOURCE_DIR) + "/config/node_template.yaml");
  ASSERT_EQ(docs.size(), 1u);
  std::map<std::string, std::string> values;
  for (const auto& e : docs.front()) {
    ASSERT_FALSE(e.is_list) << e.key;
    values[e.key] = e.values.front();
  }
  ASSERT_EQ(values.size(), node_keys().size());
  for (const auto& k : node_keys()) {
    ASSERT_EQ(values.count(k.key), 1u) << k.key << " is not in config/node_template.yaml";
    // The same value: numbers compared as numbers (YAML gives the shortest
    // text of a float, the table its own), names and booleans as text.
    char* end_yaml = nullptr;
    char* end_default = nullptr;
    const double v_yaml = std::strtod(values[k.key].c_str(), &end_yaml);
    const double v_default = std::strtod(k.default_value.c_str(), &end_default);
    if (!values[k.key].empty() && *end_yaml == '\0' && !k.default_value.empty() && *end_default == '\0') {
      EXPECT_EQ(v_yaml, v_default) << k.key;
    } else {
      EXPECT_EQ(values[k.key], k.default_value) << k.key;
    }
  }
  const NodeConfig loaded = node_setup_from_values(values).config;
  const NodeConfig defaults;
  EXPECT_EQ(loaded.real_time_factor, defaults.real_time_factor);
  EXPECT_EQ(loaded.end_action, defaults.end_action);
  EXPECT_EQ(loaded.record_flush_period_s, defaults.record_flush_period_s);
  EXPECT_EQ(loaded.orbit_trail_samples, defaults.orbit_trail_samples);
  EXPECT_EQ(loaded.frame_id, defaults.frame_id);
  EXPECT_EQ(loaded.record_bag, defaults.record_bag);
}

}  // namespace
}  // namespace rotor_rub::ros_node
