// The headless runner's contract: flags, CSV grid and columns, JSON summary,
// exit status.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>

#include "cli_support.hpp"
#include "temp_dir.hpp"

namespace {

using Result = rotor_rub::test::CliResult;

Result run(const std::string& args) { return rotor_rub::test::run_cli(ROTOR_RUB_RUN, args); }

std::string read(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

const std::string kScene = std::string(ROTOR_RUB_SOURCE_DIR) + "/config/paper_runup.yaml";

}  // namespace

TEST(RunnerCli, WritesCsvOnTheGridAndSummary) {
  const Result r = run("--scene " + kScene + " --method switching --rtol 1e-6 --atol 1e-9 --rate 200 " +
                       "--set end_time_s=1.5 --csv " + rotor_rub::test::tmp() + "rr.csv --summary " +
                       rotor_rub::test::tmp() + "rr.json");
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream csv(rotor_rub::test::tmp() + "rr.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("t,x_r,y_r,x_s,y_s,", 0), 0u) << header;
  for (const char* col : {"normal_force", "in_contact"}) EXPECT_NE(header.find(col), std::string::npos);
  std::string line;
  long n = 0;
  while (std::getline(csv, line)) {
    const double t = std::stod(line.substr(0, line.find(',')));
    EXPECT_EQ(t, n / 200.0) << "sample " << n;  // exact multiples of 1/rate
    ++n;
  }
  EXPECT_EQ(n, 301);  // 0 .. 1.5 s inclusive
  const std::string json = read(rotor_rub::test::tmp() + "rr.json");
  for (const char* key : {"\"events\"", "\"kind\": \"touchdown\"", "\"steps\"", "\"rhs_evals\"", "\"wall_time_s\"",
                          "\"status\": \"ok\""}) {
    EXPECT_NE(json.find(key), std::string::npos) << key;
  }
}

TEST(RunnerCli, BadInputExitsNonZeroWithOneLineReason) {
  Result r = run("--scene " + kScene + " --set clearance_m=-1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("clearance_m"), std::string::npos) << r.err;
  r = run("--scene " + kScene + " --method euler");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("accepted"), std::string::npos) << r.err;
  r = run("--scene /nonexistent.yaml");
  EXPECT_EQ(r.status, 2);
  r = run("--scene " + kScene + " --bogus");
  EXPECT_EQ(r.status, 2);
  // A bad value in the file is an error even where a flag overrides its key
  // (the case: output_rate_hz: abc with --rate 1000 used to run).
  std::ofstream(rotor_rub::test::tmp() + "rr_bad_rate.yaml") << "output_rate_hz: abc\n";
  r = run("--scene " + rotor_rub::test::tmp() + "rr_bad_rate.yaml --rate 1000 --set end_time_s=0.1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("output_rate_hz"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(rotor_rub::test::tmp() + "rr_bad_rate.yaml:1:17"), std::string::npos) << r.err;
  // `rtol:1.0e-4` (no space) is no key to YAML or rosparam: an error, not rtol.
  std::ofstream(rotor_rub::test::tmp() + "rr_nospace.yaml") << "method: switching\nrtol:1.0e-4\n";
  r = run("--scene " + rotor_rub::test::tmp() + "rr_nospace.yaml");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("rr_nospace.yaml:"), std::string::npos) << r.err;
}

TEST(RunnerCli, FailedRunExitsWithItsClassAndKeepsTheSamples) {
  // A step budget far too small: the run stalls after 300 steps.
  const Result r = run("--scene " + kScene + " --set max_steps=300 --csv " + rotor_rub::test::tmp() + "rr_fail.csv");
  EXPECT_EQ(r.status, 3) << r.err;
  EXPECT_NE(r.err.find("stalled"), std::string::npos) << r.err;
  const std::string csv = read(rotor_rub::test::tmp() + "rr_fail.csv");
  EXPECT_GT(std::count(csv.begin(), csv.end(), '\n'), 10);
}

TEST(RunnerCli, HelpDescribesEveryOption) {
  const Result r = run("--help");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(rotor_rub::test::missing_options(r.out, {"--scene", "--method", "--rtol", "--atol", "--set", "--rate",
                                                     "--csv", "--summary", "--quiet", "--list-keys", "--help"}),
            "")
      << r.out;
  EXPECT_NE(r.out.find("[Hz]"), std::string::npos) << r.out;  // units where an option has one
  // A scene key's option says the key's default: the integrator's is auto.
  EXPECT_NE(r.out.find("sets scene key integrator (the key's default: auto)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Exit status"), std::string::npos) << r.out;
  EXPECT_EQ(run("-h").status, 0);
}

TEST(RunnerCli, UsageErrorsNameTheOptionTheValueAndTheRange) {
  auto expect_usage = [](const Result& r, std::initializer_list<const char*> parts) {
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;  // one line
    for (const char* p : parts) EXPECT_NE(r.err.find(p), std::string::npos) << p << " in " << r.err;
  };
  expect_usage(run("--scene " + kScene + " --rate abc"), {"--rate", "'abc'", "not a number", "accepted: (0, "});
  expect_usage(run("--scene " + kScene + " --rate -5"), {"--rate", "-5", "out of range", "accepted: (0, "});
  expect_usage(run("--scene " + kScene + " --rtol 2"), {"--rtol", "2", "out of range", "accepted: [1e-14, 1]"});
  expect_usage(run("--scene " + kScene + " --atol x1"), {"--atol", "'x1'", "not a number"});
  expect_usage(run("--scene " + kScene + " --set rtol"), {"--set", "'rtol'", "key=value"});
  expect_usage(run("--scene " + kScene + " --set rtol=abc"), {"--set", "'abc'", "rtol", "accepted"});
  // A bad --set is an error even where a flag overrides the same key.
  expect_usage(run("--scene " + kScene + " --set rtol=abc --rtol 1e-6"), {"--set", "'abc'"});
  expect_usage(run("--scene " + kScene + " --rate"), {"--rate"});
  expect_usage(run("--scene " + kScene + " --bogus"), {"unknown option '--bogus'"});
  expect_usage(run("--scene /nonexistent.yaml"), {"--scene", "/nonexistent.yaml"});
  expect_usage(run("--rtol 1e-6"), {"--scene is required"});
}

// The keyphasor and probe CSVs (part of issue 17): a mark every 2 pi / w at a
// constant speed; the probes at their own rate; --probes without a probe rate
// is bad input naming the key.
TEST(RunnerCli, KeyphasorAndProbeCsvs) {
  Result r = run("--scene " + kScene +
                 " --set initial_speed_rad_per_s=100 --set target_speed_rad_per_s=100 --set end_time_s=1"
                 " --set probe_rate_hz=2000 --keyphasor " +
                 rotor_rub::test::tmp() + "rr_kp.csv --probes " + rotor_rub::test::tmp() + "rr_pr.csv --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream kp(rotor_rub::test::tmp() + "rr_kp.csv");
  std::string line;
  std::getline(kp, line);
  EXPECT_EQ(line, "t,revolution,speed");
  int n = 0;
  while (std::getline(kp, line)) {
    ++n;
    EXPECT_NEAR(std::stod(line.substr(0, line.find(','))), 2 * M_PI * n / 100.0, 1e-12) << line;
  }
  EXPECT_EQ(n, 15);  // 100 rad/s for 1 s: 15.9 revolutions
  const std::string probes = read(rotor_rub::test::tmp() + "rr_pr.csv");
  EXPECT_EQ(probes.rfind("t,x_V,y_V,x_m,y_m\n", 0), 0u);
  EXPECT_EQ(std::count(probes.begin(), probes.end(), '\n'), 2001);  // header + 2000 samples
  r = run("--scene " + kScene + " --set end_time_s=0.1 --probes " + rotor_rub::test::tmp() + "rr_pr0.csv");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("probe_rate_hz"), std::string::npos) << r.err;
}

// A flexible rotor's shaft (--shaft): a row per node and sample after t = 0,
// the nodes along the rotor file's shaft, the rub station's node where the
// samples put the rotor (the same dense output at the same instant); the
// Jeffcott has no shaft: bad input naming rotor_file.
TEST(RunnerCli, ShaftCsvOfAFlexibleRotor) {
  const std::string seal = std::string(ROTOR_RUB_SOURCE_DIR) + "/config/seal_rub_runup.yaml";
  const std::string shaft_path = rotor_rub::test::tmp() + "rr_shaft.csv";
  const std::string csv_path = rotor_rub::test::tmp() + "rr_seal.csv";
  Result r = run("--scene " + seal + " --set end_time_s=1.3 --rate 200 --csv " + csv_path + " --shaft " + shaft_path +
                 " --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto rows = rotor_rub::test::read_rows(shaft_path);
  const auto samples = rotor_rub::test::read_rows(csv_path);
  ASSERT_EQ(samples.size(), 261u);     // 0 .. 1.3 s at 200 Hz
  ASSERT_EQ(rows.size(), 13u * 260u);  // 13 nodes (12 elements of 0.1 m), samples after t = 0
  EXPECT_EQ(read(shaft_path).rfind("t,node,z_m,x_m,y_m\n", 0), 0u);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const std::size_t node = i % 13, k = i / 13 + 1;
    ASSERT_EQ(std::stoul(rows[i].at("node")), node);
    EXPECT_NEAR(std::stod(rows[i].at("z_m")), 0.1 * node, 1e-12);
    EXPECT_EQ(std::stod(rows[i].at("t")), std::stod(samples[k].at("t")));
    if (node == 6) {  // the rub station
      EXPECT_NEAR(std::stod(rows[i].at("x_m")), std::stod(samples[k].at("x_r")), 1e-15) << k;
      EXPECT_NEAR(std::stod(rows[i].at("y_m")), std::stod(samples[k].at("y_r")), 1e-15) << k;
    }
  }
  r = run("--scene " + kScene + " --set end_time_s=0.1 --shaft " + shaft_path);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("rotor_file"), std::string::npos) << r.err;
}
