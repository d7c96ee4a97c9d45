// The headless runner's contract: flags, CSV grid and columns, JSON summary,
// exit status.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_support.hpp"

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
                       "--set end_time_s=1.5 --csv /tmp/rr.csv --summary /tmp/rr.json");
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream csv("/tmp/rr.csv");
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
  const std::string json = read("/tmp/rr.json");
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
}

TEST(RunnerCli, FailedRunExitsWithItsClassAndKeepsTheSamples) {
  // A step budget far too small: the run stalls after 300 steps.
  const Result r = run("--scene " + kScene + " --set max_steps=300 --csv /tmp/rr_fail.csv");
  EXPECT_EQ(r.status, 3) << r.err;
  EXPECT_NE(r.err.find("stalled"), std::string::npos) << r.err;
  const std::string csv = read("/tmp/rr_fail.csv");
  EXPECT_GT(std::count(csv.begin(), csv.end(), '\n'), 10);
}
