// rotor_rub_compare given what it cannot use: a missing file, a truncated bag,
// a file that is no bag, a bag without rotor states. Each is a clear error
// (exit 2, one line naming the file and the problem), never a crash.
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <std_msgs/String.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "../core/cli_support.hpp"
#include "../core/temp_dir.hpp"
#include "rotor_rub_msgs/RotorState.h"
#include "rotor_rub_sim/ros/bag_appender.hpp"

namespace {

using Result = rotor_rub::test::CliResult;

Result compare(const std::string& args) { return rotor_rub::test::run_cli(ROTOR_RUB_COMPARE, args); }

void expect_clear_error(const Result& r, const std::string& part) {
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find(part), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("terminate"), std::string::npos) << r.err;
}

// A real recording: 2000 states, large enough for several chunks.
void write_states(const std::string& path) {
  rotor_rub::ros_node::BagAppender bag;
  bag.open(path, 16 * 1024);
  for (uint32_t i = 0; i < 2000; ++i) {
    rotor_rub_msgs::RotorState m;
    m.sample_index = i;
    m.header.stamp = ros::Time(1, i * 100000);
    bag.write("/sim/state", m.header.stamp, m);
  }
}

}  // namespace

TEST(CompareCli, MissingFile) {
  const Result r = compare(rotor_rub::test::tmp() + "no_such_rotor_rub.bag");
  expect_clear_error(r, "no such file");
  EXPECT_EQ(r.err.find("reindex"), std::string::npos) << r.err;  // reindex mends unclosed bags only
}

TEST(CompareCli, TruncatedBag) {
  write_states(rotor_rub::test::tmp() + "rotor_rub_whole.bag");
  std::ifstream in(rotor_rub::test::tmp() + "rotor_rub_whole.bag", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 20000u);
  std::ofstream(rotor_rub::test::tmp() + "rotor_rub_truncated.bag", std::ios::binary)
      << bytes.substr(0, bytes.size() / 2);
  expect_clear_error(compare(rotor_rub::test::tmp() + "rotor_rub_truncated.bag"), "rosbag reindex");
  // The whole one is fine: the tool itself works on this bag. It holds states
  // only (as `rosbag record` of one topic would): the figures it lacks print
  // as "-", never as nan or -1.
  const Result whole = compare(rotor_rub::test::tmp() + "rotor_rub_whole.bag");
  EXPECT_EQ(whole.status, 0) << whole.err;
  EXPECT_EQ(whole.out.find("nan"), std::string::npos) << whole.out;
  EXPECT_EQ(whole.out.find(" -1 "), std::string::npos) << whole.out;
  EXPECT_NE(whole.out.find("-: not in the run"), std::string::npos) << whole.out;
}

TEST(CompareCli, NotABag) {
  std::ofstream(rotor_rub::test::tmp() + "rotor_rub_foreign.bag") << "these are not the bags you are looking for\n";
  const Result r = compare(rotor_rub::test::tmp() + "rotor_rub_foreign.bag");
  expect_clear_error(r, "is not a rosbag 2.0 file");
  EXPECT_EQ(r.err.find("reindex"), std::string::npos) << r.err;
}

TEST(CompareCli, BagWithoutRotorStates) {
  {
    rosbag::Bag b(rotor_rub::test::tmp() + "rotor_rub_other.bag", rosbag::bagmode::Write);
    std_msgs::String s;
    s.data = "hello";
    b.write("/chatter", ros::Time(1, 0), s);
  }
  expect_clear_error(compare(rotor_rub::test::tmp() + "rotor_rub_other.bag"),
                     "holds no rotor_rub_msgs/RotorState topic");
}

TEST(CompareCli, HelpDescribesEveryOption) {
  const Result r = compare("--help");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(rotor_rub::test::missing_options(r.out, {"BAG", "--runner", "--reference", "--csv", "--quiet", "--help"}),
            "")
      << r.out;
}

// The tool has no numeric option: its usage errors are an unknown option, a
// missing value, nothing to compare and a reference that names no run.
TEST(CompareCli, UsageErrors) {
  expect_clear_error(compare("--bogus"), "unknown option '--bogus'");
  expect_clear_error(compare("--runner"), "--runner");
  expect_clear_error(compare("--quiet"), "no runs given");
  write_states(rotor_rub::test::tmp() + "rotor_rub_usage.bag");
  expect_clear_error(compare(rotor_rub::test::tmp() + "rotor_rub_usage.bag --reference nosuchrun"),
                     "no run named 'nosuchrun'");
  // Bags and --runner in any order: the options take one value each.
  const Result r = compare("--quiet " + rotor_rub::test::tmp() + "rotor_rub_usage.bag --csv " + rotor_rub::test::tmp() +
                           "rotor_rub_usage.csv");
  EXPECT_EQ(r.status, 0) << r.err;
}
