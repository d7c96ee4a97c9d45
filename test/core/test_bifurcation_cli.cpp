// rotor_rub_bifurcation end to end: its classes against the closed forms of
// core/steady_response.hpp (no contact below the rub onset, the unbalance
// response's Poincare point, synchronous full rub on the run-up with the
// closed form's normal force, the no-contact branch on the run-down where both
// coexist: the hysteresis), shards that merge into the unsplit result, and bad
// input.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "cli_support.hpp"
#include "rotor_rub_sim/core/scene_file.hpp"
#include "rotor_rub_sim/core/steady_response.hpp"
#include "temp_dir.hpp"

namespace {

using rotor_rub::test::read_rows;
using rotor_rub::test::Row;
namespace core = rotor_rub::core;

rotor_rub::test::CliResult bif(const std::string& args) {
  return rotor_rub::test::run_cli(ROTOR_RUB_BIFURCATION, args);
}

const std::string kScene = std::string(ROTOR_RUB_SOURCE_DIR) + "/config/paper_runup.yaml";
// 40 to 200 rad/s in 4 rad/s bins; ramps at 2 rad/s^2 (2 s per bin).
const std::string kArgs = "--scene " + kScene +
                          " --speed-from 40 --speed-to 200 --speeds 41 --settle-s 10 --revolutions 64 "
                          "--ramp-accel 2";
// The ramp sweeps N(w) through a 4 rad/s bin and lags it: the bin's mean
// normal force is the closed form's at the bin's centre within 2 % (measured
// within 0.6 % from 80 to 160 rad/s).
constexpr double kRampForceRelTol = 0.02;
// A constant-speed run from rest after 10 s: the transient has decayed by
// exp(-zeta w_n 10 s) = 2e-7 of its 1 mm; the integration at rtol 1e-7 adds
// less (measured 2.5e-10 m in all; 1.5e-9 m at rtol 1e-6 on dop853).
constexpr double kPoincarePointTol_m = 1e-6 * 1e-3;

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace

TEST(BifurcationCli, HelpDescribesEveryOption) {
  const auto r = bif("--help");
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(rotor_rub::test::missing_options(
                r.out, {"--scene", "--grid", "--set", "--out", "--speed-from", "--speed-to", "--speeds", "--settle-s",
                        "--revolutions", "--ramp-accel", "--directions", "--points-per-bin", "--jobs", "--shard",
                        "--count-runs", "--merge", "[rad/s]", "[rad/s^2]", "[s]"}),
            "");
}

TEST(BifurcationCli, RampsAgreeWithTheClosedFormsAndShowTheHysteresis) {
  const auto r = bif(kArgs + " --directions up,down --out " + rotor_rub::test::tmp() + "rr_bif.csv");
  ASSERT_EQ(r.status, 0) << r.err;
  // The summary names what ran, auto resolved (the paper scene's switching at rtol 1e-6: dop853).
  EXPECT_NE(r.err.find("; switching on dop853)"), std::string::npos) << r.err;
  const core::ModelParameters p = core::load_scene(kScene).model;
  const double onset = core::rub_onset_speed_rad_per_s(p);
  int full_rub_checked = 0, hysteresis_checked = 0;
  for (const Row& row : read_rows(rotor_rub::test::tmp() + "rr_bif.csv")) {
    const double w = std::stod(row.at("speed_rad_per_s"));
    const std::string& dir = row.at("direction");
    ASSERT_EQ(row.at("status"), "ok") << w;
    if (w < onset - 4.0) {  // a bin wholly below the onset
      EXPECT_EQ(row.at("class"), "no_contact") << dir << " " << w;
      continue;
    }
    const auto branch = core::synchronous_full_rub(p, w);
    if (dir == "up" && w >= 80.0 && w <= 160.0) {
      ASSERT_FALSE(branch.empty()) << w;
      EXPECT_EQ(row.at("class"), "full_rub") << w;
      EXPECT_EQ(row.at("whirl"), "forward") << w;
      EXPECT_NEAR(std::stod(row.at("mean_normal_force_N")), branch.front().normal_force_N,
                  kRampForceRelTol * branch.front().normal_force_N)
          << w;
      ++full_rub_checked;
    }
    // Coming down, the rotor stays on the no-contact orbit where both it
    // (|Z| < C) and the full-rub branch exist: the jump is not reversible.
    if (dir == "down" && w >= 100.0 && w <= 160.0) {
      ASSERT_FALSE(branch.empty()) << w;
      ASSERT_LT(std::abs(core::unbalance_response_m(p, w)), p.clearance_m) << w;
      EXPECT_EQ(row.at("class"), "no_contact") << w;
      ++hysteresis_checked;
    }
  }
  EXPECT_EQ(full_rub_checked, 21);
  EXPECT_EQ(hysteresis_checked, 16);
}

TEST(BifurcationCli, ConstantSpeedPoincarePointIsTheUnbalanceResponse) {
  const auto r = bif("--scene " + kScene +
                     " --speed-from 40 --speed-to 60 --speeds 3 --settle-s 10 --revolutions 64 --directions constant "
                     "--set rtol=1e-7 "
                     "--out " +
                     rotor_rub::test::tmp() + "rr_bif_c.csv");
  ASSERT_EQ(r.status, 0) << r.err;
  const core::ModelParameters p = core::load_scene(kScene).model;
  const auto rows = read_rows(rotor_rub::test::tmp() + "rr_bif_c.csv");
  ASSERT_EQ(rows.size(), 3u);
  for (const Row& row : rows) {
    EXPECT_EQ(row.at("class"), "no_contact");
    EXPECT_EQ(row.at("motion"), "periodic");
    EXPECT_EQ(row.at("period"), "1");
    EXPECT_EQ(row.at("points"), "64");
  }
  int checked = 0;
  for (const Row& pt : read_rows(rotor_rub::test::tmp() + "rr_bif_c.csv.points.csv")) {
    const auto z = core::unbalance_response_m(p, std::stod(pt.at("speed_rad_per_s")));
    EXPECT_NEAR(std::stod(pt.at("x_rel_m")), z.real(), kPoincarePointTol_m);
    EXPECT_NEAR(std::stod(pt.at("y_rel_m")), z.imag(), kPoincarePointTol_m);
    ++checked;
  }
  EXPECT_EQ(checked, 3 * 64);
}

TEST(BifurcationCli, ShardsMergeIntoTheUnsplitResult) {
  const std::string small = "--scene " + kScene +
                            " --set friction_coefficient=0.1,0.3 --speed-from 60 --speed-to 140 --speeds 5 "
                            "--settle-s 3 --revolutions 64 --ramp-accel 20 --jobs 1";
  auto r = bif(small + " --count-runs");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, "14\n");  // 2 frictions x (5 speeds + up + down)
  ASSERT_EQ(bif(small + " --out " + rotor_rub::test::tmp() + "rr_bif_all.csv").status, 0);
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(bif(small + " --shard " + std::to_string(i) + "/3 --out " + rotor_rub::test::tmp() + "rr_bif_" +
                  std::to_string(i) + ".csv")
                  .status,
              0);
  }
  r = bif("--merge " + rotor_rub::test::tmp() + "rr_bif_merged.csv " + rotor_rub::test::tmp() + "rr_bif_2.csv " +
          rotor_rub::test::tmp() + "rr_bif_0.csv " + rotor_rub::test::tmp() + "rr_bif_1.csv");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(slurp(rotor_rub::test::tmp() + "rr_bif_merged.csv"), slurp(rotor_rub::test::tmp() + "rr_bif_all.csv"));
  EXPECT_EQ(slurp(rotor_rub::test::tmp() + "rr_bif_merged.csv.points.csv"),
            slurp(rotor_rub::test::tmp() + "rr_bif_all.csv.points.csv"));
  // A missing shard is an error naming the run.
  r = bif("--merge " + rotor_rub::test::tmp() + "rr_bif_merged.csv " + rotor_rub::test::tmp() + "rr_bif_0.csv " +
          rotor_rub::test::tmp() + "rr_bif_1.csv");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("is in no shard"), std::string::npos) << r.err;
}

TEST(BifurcationCli, BadInputIsOneLineAndExitTwo) {
  auto r = bif("--speed-from 100 --speed-to 50 --out " + rotor_rub::test::tmp() + "rr_bif_bad.csv");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--speed-to"), std::string::npos) << r.err;
  r = bif("--speeds 0 --out " + rotor_rub::test::tmp() + "rr_bif_bad.csv");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--speeds"), std::string::npos) << r.err;
  r = bif("--set frictoin_coefficient=0.1 --out " + rotor_rub::test::tmp() + "rr_bif_bad.csv");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("friction_coefficient"), std::string::npos) << r.err;  // the nearest key
  // One speed is a grid of one (constant runs only).
  r =
      bif("--speeds 1 --speed-from 100 --speed-to 100 --directions constant --settle-s 1 --revolutions 16 "
          "--out " +
          rotor_rub::test::tmp() + "rr_bif_one.csv");
  EXPECT_EQ(r.status, 0) << r.err;
  r = bif("--speeds 1 --speed-from 100 --speed-to 100 --out " + rotor_rub::test::tmp() +
          "rr_bif_bad.csv");  // ramps need a range
  EXPECT_EQ(r.status, 2);
  r = bif("--directions sideways --out " + rotor_rub::test::tmp() + "rr_bif_bad.csv");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("sideways"), std::string::npos) << r.err;
}
