// rotor_rub_sim_node's own command line, without a master: --help and
// --list-keys (scripts/gen_scene_template.py reads its format), ROS arguments
// passed through, an unknown flag an error.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "../core/cli_support.hpp"
#include "rotor_rub_sim/ros/node_config.hpp"

namespace {

using Result = rotor_rub::test::CliResult;

// No master at this URI: whatever passes here needs none.
Result node(const std::string& args) {
  return rotor_rub::test::run_cli(ROTOR_RUB_NODE, args, "env ROS_MASTER_URI=http://127.0.0.1:1");
}

// --list-keys' lines, in rotor_rub_run --list-keys' format.
std::string expected_list() {
  std::string out;
  char line[1024];
  for (const auto& k : rotor_rub::ros_node::node_keys()) {
    std::snprintf(line, sizeof line, "%-34s default %-10s accepted %s\n    %s\n", k.key.c_str(),
                  k.default_value.empty() ? "\"\"" : k.default_value.c_str(), k.accepted.c_str(),
                  k.description.c_str());
    out += line;
  }
  return out;
}

}  // namespace

TEST(NodeCli, HelpExitsZeroWithoutAMaster) {
  const Result r = node("--help");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(rotor_rub::test::missing_options(r.out, {"--help", "--list-keys", "__name:=", "_key:=value"}), "") << r.out;
  EXPECT_EQ(node("-h").status, 0);
}

TEST(NodeCli, ListKeysPrintsTheNodeKeyTable) {
  const Result r = node("--list-keys");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, expected_list());
  // With ROS arguments, as rosrun and roslaunch add them.
  const Result ros_args = node("__name:=cli_test __ns:=/cli_test _real_time_factor:=0 state:=other_state --list-keys");
  EXPECT_EQ(ros_args.status, 0) << ros_args.err;
  EXPECT_EQ(ros_args.out, expected_list());
}

TEST(NodeCli, UnknownFlagIsAUsageError) {
  for (const char* args : {"--bogus", "__name:=cli_test --bogus", "stray"}) {
    const Result r = node(args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_NE(r.err.find("rotor_rub_sim_node: "), std::string::npos) << r.err;
  }
  EXPECT_NE(node("--bogus").err.find("unknown option '--bogus'"), std::string::npos);
}
