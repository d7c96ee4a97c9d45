// The sweep runner's contract: one CSV row per run with its status and error
// columns, the reference's error against itself exactly zero, a failing run
// kept as a row with its class, shards that merge into the unsplit result.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "temp_dir.hpp"

namespace {

using Result = rotor_rub::test::CliResult;

Result sweep(const std::string& args, const std::string& prefix = "") {
  return rotor_rub::test::run_cli(ROTOR_RUB_SWEEP, args, prefix);
}

using rotor_rub::test::read_rows;
using rotor_rub::test::Row;
using rotor_rub::test::split;

const std::string kScene = std::string(ROTOR_RUB_SOURCE_DIR) + "/config/paper_runup.yaml";

// A small grid: two methods, a run that spends its step budget, and the
// reference's own settings (switching on dopri5, sweep_reference.cpp). 1.5 s covers the first contacts (from 1.11 s).
const std::string kGrid =
    "method: [switching, iteration]\n"
    "rtol: 1.0e-5\n"
    "atol_per_rtol: 1.0e-3\n"
    "---\n"
    "method: penalty\n"
    "max_steps: 50\n"
    "---\n"
    "method: switching\n"
    "integrator: dopri5\n"
    "rtol: 1.0e-10\n"
    "atol: 1.0e-13\n"
    "---\n"
    "method: penalty\n"
    "max_wall_time_s: 1.0e-4\n";

std::string common_args() {
  std::ofstream(rotor_rub::test::tmp() + "rotor_rub_sweep_grid.yaml") << kGrid;
  return "--scene " + kScene + " --grid " + rotor_rub::test::tmp() +
         "rotor_rub_sweep_grid.yaml --set end_time_s=1.5 --repeats 1 --jobs 2 --no-progress"
         " --reference-rtol 1e-10 --reference-atol 1e-13 --error-rate 10000";
}

double num(const Row& r, const std::string& k) { return std::stod(r.at(k)); }

}  // namespace

TEST(SweepCli, RowsStatusesAndErrors) {
  const Result r = sweep(common_args() + " --out " + rotor_rub::test::tmp() + "sweep_all.csv");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto rows = read_rows(rotor_rub::test::tmp() + "sweep_all.csv");
  ASSERT_EQ(rows.size(), 5u);
  const char* methods[] = {"switching", "iteration", "penalty", "switching", "penalty"};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].at("run_id"), std::to_string(i));
    EXPECT_EQ(rows[i].at("runs_total"), "5");
    EXPECT_EQ(rows[i].at("method"), methods[i]);
  }
  // The accurate runs: ok, compared over the whole run, errors small but
  // not zero (a different tolerance), first contact within 1e-4 s.
  for (int i : {0, 1}) {
    EXPECT_EQ(rows[i].at("status"), "ok") << rows[i].at("message");
    EXPECT_EQ(rows[i].at("compared_samples"), "15001");
    EXPECT_GT(num(rows[i], "max_rotor_err_m"), 0.0);
    EXPECT_LT(num(rows[i], "max_rotor_err_m"), 1e-4);  // 5 % of the 2 mm clearance
    EXPECT_LT(std::abs(num(rows[i], "first_contact_err_s")), 1e-4);
    EXPECT_GT(num(rows[i], "wall_time_s"), 0.0);
    EXPECT_EQ(rows[i].at("atol"), "1e-08");  // atol_per_rtol resolved
  }
  // The step budget: a stalled run kept as a row with its class, its message
  // and the samples it delivered before failing.
  EXPECT_EQ(rows[2].at("status"), "stalled");
  EXPECT_NE(rows[2].at("message").find("step budget"), std::string::npos) << rows[2].at("message");
  EXPECT_LT(std::stoul(rows[2].at("compared_samples")), 15001u);
  EXPECT_TRUE(std::isfinite(num(rows[2], "failure_time_s")));
  // The reference against itself: every error exactly zero.
  EXPECT_EQ(rows[3].at("status"), "ok");
  for (const char* k : {"max_rotor_err_m", "rms_rotor_err_m", "max_stator_err_m", "first_contact_err_s",
                        "last_contact_end_err_s", "impulse_window_err_rel"}) {
    EXPECT_EQ(num(rows[3], k), 0.0) << k;
  }
  EXPECT_EQ(num(rows[3], "impulse_windows_within_5pct"), 1.0);
  EXPECT_EQ(num(rows[3], "max_event_err_s"), 0.0);
  EXPECT_TRUE(std::isnan(num(rows[3], "event_mismatch_s"))) << "every touchdown and lift-off agrees";
  // No witness: no horizon, the whole run judged.
  for (const auto& row : rows) EXPECT_TRUE(std::isinf(num(row, "horizon_s")));
  // A run's own wall budget is not its reference's (issue 15: the reference
  // inherited it and failed with the run).
  EXPECT_EQ(rows[4].at("status"), "timed_out") << rows[4].at("message");
  EXPECT_EQ(rows[4].at("message").find("reference failed"), std::string::npos) << rows[4].at("message");
}

// With a witness (the iteration method at the reference's tolerances): on the
// paper's run-up the two rigid methods agree to far below 1e-4 m, so the
// horizon is the whole run and the runs are judged as without it.
TEST(SweepCli, AWitnessThatAgreesLeavesNoHorizon) {
  const Result r = sweep("--scene " + kScene +
                         " --set method=switching --set rtol=1e-5 --set atol_per_rtol=1e-3 --set end_time_s=1.5"
                         " --repeats 1 --jobs 1 --no-progress --error-rate 10000 --witness --out " +
                         rotor_rub::test::tmp() + "sweep_witness.csv");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto rows = read_rows(rotor_rub::test::tmp() + "sweep_witness.csv");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].at("status"), "ok") << rows[0].at("message");
  EXPECT_TRUE(std::isinf(num(rows[0], "horizon_s")));
  EXPECT_EQ(num(rows[0], "max_rotor_err_in_horizon_m"), num(rows[0], "max_rotor_err_m"));
  // Every contact where the reference has it, within the 1 ms window (the
  // later impacts of the rub drift by a fraction of it at rtol 1e-5).
  EXPECT_TRUE(std::isnan(num(rows[0], "event_mismatch_s")));
  EXPECT_GT(num(rows[0], "max_event_err_s"), 0.0);
  EXPECT_LT(num(rows[0], "max_event_err_s"), 1e-3);
}

TEST(SweepCli, ShardsMergeIntoTheUnsplitResult) {
  ASSERT_EQ(sweep(common_args() + " --out " + rotor_rub::test::tmp() + "sweep_full.csv").status, 0);
  ASSERT_EQ(sweep(common_args() + " --shard 0/3 --out " + rotor_rub::test::tmp() + "sweep_s0.csv").status, 0);
  ASSERT_EQ(sweep(common_args() + " --shard 1/3 --out " + rotor_rub::test::tmp() + "sweep_s1.csv").status, 0);
  ASSERT_EQ(sweep(common_args() + " --shard 2/3 --out " + rotor_rub::test::tmp() + "sweep_s2.csv").status, 0);
  // Out of order on purpose: the merge sorts by run.
  const Result m =
      sweep("--merge " + rotor_rub::test::tmp() + "sweep_merged.csv " + rotor_rub::test::tmp() + "sweep_s2.csv " +
            rotor_rub::test::tmp() + "sweep_s0.csv " + rotor_rub::test::tmp() + "sweep_s1.csv");
  ASSERT_EQ(m.status, 0) << m.err;
  auto full = read_rows(rotor_rub::test::tmp() + "sweep_full.csv");
  auto merged = read_rows(rotor_rub::test::tmp() + "sweep_merged.csv");
  ASSERT_EQ(full.size(), merged.size());
  for (std::size_t i = 0; i < full.size(); ++i) {
    // Wall time is a measurement; everything else is deterministic, except
    // where a run spent its wall budget: it stops at a step that depends on
    // the machine's speed, so only its settings, status and message are.
    if (full[i].at("status") == "timed_out") {
      for (const char* k : {"method", "status", "message", "other_settings"}) {
        EXPECT_EQ(full[i].at(k), merged[i].at(k)) << "run " << i << " " << k;
      }
      continue;
    }
    full[i].erase("wall_time_s");
    merged[i].erase("wall_time_s");
    EXPECT_EQ(full[i], merged[i]) << "run " << i;
  }
  // A missing shard is an error that names the missing runs.
  const Result bad = sweep("--merge " + rotor_rub::test::tmp() + "sweep_bad.csv " + rotor_rub::test::tmp() +
                           "sweep_s0.csv " + rotor_rub::test::tmp() + "sweep_s1.csv");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("missing: 2"), std::string::npos) << bad.err;
}

TEST(SweepCli, BadInputNamesTheProblem) {
  Result r = sweep("--scene " + kScene + " --set rtoll=1e-3 --out " + rotor_rub::test::tmp() + "sweep_bad.csv");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("did you mean 'rtol'"), std::string::npos) << r.err;
  r = sweep("--scene " + kScene + " --set rtol=1e-3 --shard 3/3 --out " + rotor_rub::test::tmp() + "sweep_bad.csv");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("accepted: I/N with 0 <= I < N"), std::string::npos) << r.err;
  r = sweep("--scene " + kScene + " --set rtol=1e-3");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
}

TEST(SweepCli, HelpDescribesEveryOption) {
  const Result r = sweep("--help");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(rotor_rub::test::missing_options(
                r.out, {"--scene", "--grid", "--set", "--out", "--repeats", "--jobs", "--shard", "--profile", "--cache",
                        "--error-rate", "--window-ms", "--reference-rtol", "--reference-atol", "--inaccurate-above",
                        "--no-progress", "--merge", "--help"}),
            "")
      << r.out;
  for (const char* unit : {"[Hz]", "[ms]", "[m]"}) EXPECT_NE(r.out.find(unit), std::string::npos) << unit;
}

TEST(SweepCli, UsageErrorsNameTheOptionTheValueAndTheRange) {
  auto expect_usage = [](const std::string& args, std::initializer_list<const char*> parts) {
    const Result r =
        sweep("--scene " + kScene + " --set rtol=1e-3 --out " + rotor_rub::test::tmp() + "sweep_usage.csv " + args);
    EXPECT_EQ(r.status, 2) << args << ": " << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;  // one line
    for (const char* p : parts) EXPECT_NE(r.err.find(p), std::string::npos) << p << " in " << r.err;
  };
  expect_usage("--repeats abc", {"--repeats", "'abc'", "not an integer", "accepted: integer in [1, 1000]"});
  expect_usage("--repeats 2.5", {"--repeats", "'2.5'", "not an integer"});
  expect_usage("--jobs 0", {"--jobs", "value 0", "out of range", "accepted: integer in [1, 1024]"});
  expect_usage("--error-rate fast", {"--error-rate", "'fast'", "not a number", "accepted: [1, 10000000]"});
  expect_usage("--window-ms 1e9", {"--window-ms", "1e9", "out of range", "accepted: [0.001, 1000]"});
  expect_usage("--reference-rtol 1e-3", {"--reference-rtol", "1e-3", "out of range", "accepted: [1e-14, 1e-06]"});
  expect_usage("--reference-atol nan", {"--reference-atol", "'nan'", "not a finite number"});
  expect_usage("--inaccurate-above -1", {"--inaccurate-above", "-1", "out of range"});
  expect_usage("--set rtol", {"--set", "'rtol'"});
  expect_usage("--grid /nonexistent_grid.yaml", {"--grid", "/nonexistent_grid.yaml"});
  expect_usage("--bogus", {"unknown option '--bogus'"});
  expect_usage("--merge " + rotor_rub::test::tmp() + "a.csv " + rotor_rub::test::tmp() + "b.csv", {"excludes --merge"});
  const Result m = sweep("--merge " + rotor_rub::test::tmp() + "only_out.csv");
  EXPECT_EQ(m.status, 2);
  EXPECT_NE(m.err.find("--merge"), std::string::npos) << m.err;
}

// The default scene is the package's, found from any directory (here the
// test's own temporary one, and / without ROS_PACKAGE_PATH: then beside the
// sources it was built from).
TEST(SweepCli, DefaultSceneFromAnyDirectory) {
  for (const std::string& prefix :
       {"cd " + rotor_rub::test::tmp() + " &&", std::string("cd / && env -u ROS_PACKAGE_PATH")}) {
    const Result r = sweep(
        "--set end_time_s=0.2 --set method=switching --repeats 1 --jobs 1 --no-progress "
        "--out " +
            rotor_rub::test::tmp() + "sweep_default_scene.csv",
        prefix);
    ASSERT_EQ(r.status, 0) << prefix << ": " << r.err;
    const auto rows = read_rows(rotor_rub::test::tmp() + "sweep_default_scene.csv");
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_EQ(rows[0].at("status"), "ok") << rows[0].at("message");
    EXPECT_NE(r.err.find("/config/paper_runup.yaml)"), std::string::npos) << r.err;  // the scene it used
  }
}
