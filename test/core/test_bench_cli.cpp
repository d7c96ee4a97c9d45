// rotor_rub_bench's command line, and the package's files found from any
// directory (package_paths, which the bench and the sweep use for their
// default scene).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <stdexcept>
#include <string>

#include "cli_support.hpp"
#include "package_paths.hpp"

namespace {

using Result = rotor_rub::test::CliResult;

Result bench(const std::string& args, const std::string& prefix = "") {
  return rotor_rub::test::run_cli(ROTOR_RUB_BENCH, args, prefix);
}

void expect_usage(const Result& r, std::initializer_list<const char*> parts) {
  EXPECT_EQ(r.status, 2) << r.err;  // not -1: no abort
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(r.err.find("terminate"), std::string::npos) << r.err;
  for (const char* p : parts) EXPECT_NE(r.err.find(p), std::string::npos) << p << " in " << r.err;
}

}  // namespace

TEST(BenchCli, HelpDescribesEveryOption) {
  const Result r = bench("--help");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(rotor_rub::test::missing_options(r.out, {"--scene", "--repeats", "--error-rate", "--quick", "--help"}), "")
      << r.out;
  EXPECT_NE(r.out.find("[Hz]"), std::string::npos) << r.out;
}

TEST(BenchCli, UsageErrorsNameTheOptionTheValueAndTheRange) {
  // Issue 14: --error-rate abc was an uncaught exception (SIGABRT).
  expect_usage(bench("--error-rate abc"), {"--error-rate", "'abc'", "not a number", "accepted: (0, 10000000]"});
  expect_usage(bench("--error-rate 0"), {"--error-rate", "value 0", "out of range"});
  expect_usage(bench("--repeats many"), {"--repeats", "'many'", "not an integer", "accepted: integer in [1, 1000]"});
  expect_usage(bench("--repeats 0"), {"--repeats", "value 0", "out of range"});
  expect_usage(bench("--scene /nonexistent_scene.yaml"), {"--scene", "/nonexistent_scene.yaml"});
  expect_usage(bench("--fast"), {"unknown option '--fast'"});
}

// The default scene is the package's from any directory: here /tmp. The
// quickest whole bench there is (the paper scene, two tolerances, one repeat).
TEST(BenchCli, QuickRunFromAnyDirectory) {
  const Result r = bench("--quick --repeats 1", "cd /tmp &&");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.rfind("scene /", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("/config/paper_runup.yaml; reference"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("penalty "), std::string::npos) << r.out;
}

// An install space: <prefix>/lib/rotor_rub_sim/rotor_rub_bench finds
// <prefix>/share/rotor_rub_sim/config/paper_runup.yaml first (a short scene
// here, so the run is quick).
TEST(BenchCli, DefaultSceneBesideTheExecutableInAnInstallSpace) {
  namespace fs = std::filesystem;
  const fs::path prefix = fs::temp_directory_path() / ("rotor_rub_prefix." + std::to_string(::getpid()));
  fs::remove_all(prefix);
  fs::create_directories(prefix / "lib/rotor_rub_sim");
  fs::create_directories(prefix / "share/rotor_rub_sim/config");
  fs::copy_file(ROTOR_RUB_BENCH, prefix / "lib/rotor_rub_sim/rotor_rub_bench");
  fs::permissions(prefix / "lib/rotor_rub_sim/rotor_rub_bench", fs::perms::owner_all);
  std::ofstream(prefix / "share/rotor_rub_sim/config/paper_runup.yaml") << "end_time_s: 0.05\n";
  const Result r = rotor_rub::test::run_cli((prefix / "lib/rotor_rub_sim/rotor_rub_bench").string(),
                                            "--quick --repeats 1", "cd / &&");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.rfind("scene " + (prefix / "share/rotor_rub_sim/config/paper_runup.yaml").string() + ";", 0), 0u)
      << r.out;
  fs::remove_all(prefix);
}

TEST(PackagePaths, CandidatesInOrderAndTheErrorNamesThemAll) {
  ::setenv("ROS_PACKAGE_PATH", "/nonexistent_ws/src:/opt/nonexistent", 1);
  const auto c = rotor_rub::tools::package_file_candidates("config/x.yaml");
  ASSERT_EQ(c.size(), 4u);
  // This test's executable: <devel>/lib/rotor_rub_sim/test_bench_cli.
  EXPECT_NE(c[0].find("/share/rotor_rub_sim/config/x.yaml"), std::string::npos) << c[0];
  EXPECT_EQ(c[1], "/nonexistent_ws/src/rotor_rub_sim/config/x.yaml");
  EXPECT_EQ(c[2], "/opt/nonexistent/rotor_rub_sim/config/x.yaml");
  EXPECT_EQ(c[3], std::string(ROTOR_RUB_SOURCE_DIR) + "/config/x.yaml");
  try {
    rotor_rub::tools::find_package_file("config/no_such_scene.yaml");
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    for (const auto& p : rotor_rub::tools::package_file_candidates("config/no_such_scene.yaml")) {
      EXPECT_NE(what.find(p), std::string::npos) << p << " in " << what;
    }
  }
  // A ROS_PACKAGE_PATH entry that is the package itself (its package.xml names it).
  ::setenv("ROS_PACKAGE_PATH", ROTOR_RUB_SOURCE_DIR, 1);
  const auto own = rotor_rub::tools::package_file_candidates("config/paper_runup.yaml");
  EXPECT_NE(std::find(own.begin(), own.end(), std::string(ROTOR_RUB_SOURCE_DIR) + "/config/paper_runup.yaml"),
            own.end());
  EXPECT_EQ(rotor_rub::tools::find_package_file("config/paper_runup.yaml"),
            std::string(ROTOR_RUB_SOURCE_DIR) + "/config/paper_runup.yaml");
}
