// rotor_rub_bench's command line, and the package's files found from any
// directory (package_paths, which the bench and the sweep use for their
// default scene).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "package_paths.hpp"
#include "temp_dir.hpp"

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
  EXPECT_EQ(rotor_rub::test::missing_options(
                r.out, {"--scene", "--repeats", "--error-rate", "--quick", "--methods", "--csv", "--help"}),
            "")
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
  expect_usage(bench("--methods switching,rk45"), {"--methods", "rk45"});
}

// The rows a user compares: the switching integrators and CVODE beside them
// on a 1.5 s run (through the first contact), in the table, in the CSV the
// charts read, and CVODE's ratio against ours measured in the same run.
TEST(BenchCli, MethodsAndCsvWithCvodeBesideUs) {
  const std::string scene = rotor_rub::test::tmp() + "rotor_rub_bench_short." + std::to_string(::getpid()) + ".yaml";
  const std::string csv = scene + ".csv";
  std::ofstream(scene) << "end_time_s: 1.5\n";
  const Result r = bench("--scene " + scene + " --quick --repeats 1 --methods switching,cvode --csv " + csv);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.find("\niteration "), std::string::npos) << r.out;  // no iteration row
  EXPECT_NE(r.out.find("CVODE (adams) / ours (switching "), std::string::npos) << r.out;
  std::ifstream in(csv);
  std::string header, line;
  ASSERT_TRUE(std::getline(in, header));
  EXPECT_EQ(header.rfind("method,integrator,rtol,atol,status,wall_time_s,quiet_wall_time_s,steps,", 0), 0u) << header;
  EXPECT_NE(header.find(",max_rotor_err_m,"), std::string::npos) << header;
  auto fields = [](const std::string& text) {
    std::vector<std::string> f;
    std::stringstream ss(text);
    for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
    return f;
  };
  const auto names = fields(header);
  const auto err_col = std::find(names.begin(), names.end(), "max_rotor_err_m") - names.begin();
  int rows = 0, cvode = 0, rkf78 = 0, dop853 = 0, rosenbrock4 = 0, stiffness_switch = 0;
  while (std::getline(in, line)) {
    ++rows;
    cvode += line.rfind("cvode,", 0) == 0;
    rkf78 += line.rfind("switching,rkf78,", 0) == 0;
    dop853 += line.rfind("switching,dop853,", 0) == 0;
    rosenbrock4 += line.rfind("switching,rosenbrock4,", 0) == 0;
    stiffness_switch += line.rfind("switching,dop853_rosenbrock4,", 0) == 0;
    EXPECT_NE(line.find(",ok,"), std::string::npos) << line;
    const auto f = fields(line);
    ASSERT_EQ(f.size(), names.size()) << line;
    const double err = std::stod(f[err_col]);  // measured, and below the clearance
    EXPECT_TRUE(err >= 0.0 && err < 1e-3) << line;
  }
  EXPECT_EQ(rows, 14);  // two tolerances x (dop853_rosenbrock4, dopri5, rkf78, dop853, rosenbrock4, Adams, BDF)
  EXPECT_EQ(cvode, 4);
  EXPECT_EQ(rkf78, 2);
  EXPECT_EQ(dop853, 2);
  EXPECT_EQ(rosenbrock4, 2);
  EXPECT_EQ(stiffness_switch, 2);
  std::remove(scene.c_str());
  std::remove(csv.c_str());
}

// The default scene is the package's from any directory: here the test's own
// temporary one. The quickest whole bench there is (the paper scene, two
// tolerances, one repeat).
TEST(BenchCli, QuickRunFromAnyDirectory) {
  const Result r = bench("--quick --repeats 1", "cd " + rotor_rub::test::tmp() + " &&");
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
  const fs::path prefix = fs::path(rotor_rub::test::tmp()) / "install_prefix";
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
  const auto c = rotor_rub::cli::package_file_candidates("config/x.yaml");
  ASSERT_EQ(c.size(), 4u);
  // This test's executable: <devel>/lib/rotor_rub_sim/test_bench_cli.
  EXPECT_NE(c[0].find("/share/rotor_rub_sim/config/x.yaml"), std::string::npos) << c[0];
  EXPECT_EQ(c[1], "/nonexistent_ws/src/rotor_rub_sim/config/x.yaml");
  EXPECT_EQ(c[2], "/opt/nonexistent/rotor_rub_sim/config/x.yaml");
  EXPECT_EQ(c[3], std::string(ROTOR_RUB_SOURCE_DIR) + "/config/x.yaml");
  try {
    rotor_rub::cli::find_package_file("config/no_such_scene.yaml");
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    for (const auto& p : rotor_rub::cli::package_file_candidates("config/no_such_scene.yaml")) {
      EXPECT_NE(what.find(p), std::string::npos) << p << " in " << what;
    }
  }
  // A ROS_PACKAGE_PATH entry that is the package itself (its package.xml names it).
  ::setenv("ROS_PACKAGE_PATH", ROTOR_RUB_SOURCE_DIR, 1);
  const auto own = rotor_rub::cli::package_file_candidates("config/paper_runup.yaml");
  EXPECT_NE(std::find(own.begin(), own.end(), std::string(ROTOR_RUB_SOURCE_DIR) + "/config/paper_runup.yaml"),
            own.end());
  EXPECT_EQ(rotor_rub::cli::find_package_file("config/paper_runup.yaml"),
            std::string(ROTOR_RUB_SOURCE_DIR) + "/config/paper_runup.yaml");
}
