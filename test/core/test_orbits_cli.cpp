// rotor_rub_orbits' command line: the horizontal rotor's orbit at 60 rad/s,
// its branch with the bifurcations the core's tests hold
// (test_orbit_continuation.cpp), its CSV, orbits that stick, no orbit as exit
// status 3, and bad input as one line with exit status 2.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <utility>

#include "cli_support.hpp"
#include "temp_dir.hpp"

namespace {

using Result = rotor_rub::test::CliResult;

Result orbits(const std::string& args) { return rotor_rub::test::run_cli(ROTOR_RUB_ORBITS, args); }

std::string config(const std::string& name) { return std::string(ROTOR_RUB_SOURCE_DIR) + "/config/" + name; }

}  // namespace

TEST(OrbitsCli, TheHorizontalRotorsBranchAndItsCsv) {
  const std::string csv = rotor_rub::test::tmp() + "/orbits.csv";
  const Result r = orbits("--scene " + config("horizontal_rub.yaml") + " --speed 60 --continue 45 75 --csv " + csv);
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* line :
       {"orbit at 60.000000 rad/s: period 1 T = 0.104719755 s, stable", "impact    at t = 0.073478137 s",
        "branch 0: period_doubling at 53.0920", "branch 0: neimark_sacker at 64.8927",
        "branch 1: period_doubling at 53.0622", "it ends: the orbit's events change at the trial 52.98"}) {
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  }
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line,
            "branch,periods,speed_rad_per_s,parameter,keyphasor,x_m,y_m,radius_m,max_multiplier,stable,events,"
            "bifurcation");
  int period2 = 0, doublings = 0;
  while (std::getline(in, line)) {
    period2 += line.rfind("1,2,", 0) == 0;
    doublings += line.find(",period_doubling") != std::string::npos;
  }
  EXPECT_GT(period2, 10);
  EXPECT_EQ(doublings, 1 + 2);  // the single orbit's (one keyphasor point) and the doubled one's (two)
}

// A branch in a key of the model (--parameter) at the constant --speed.
TEST(OrbitsCli, ABranchInAKey) {
  const Result r = orbits("--scene " + config("horizontal_rub.yaml") +
                          " --speed 60 --continue 5 15 --parameter gravity_m_per_s2 --doublings 0");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("branch 0: period_doubling at 8.8465"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("9.810000 to 8.30"), std::string::npos) << r.out;
}

// The thin shaft (config/stick_slip_rub.yaml: R_r = C, f = 1, plastic) sticks
// and slips on the bore's bottom: its events and multipliers on the bore's
// tangent space; its branch, traced on that space, doubles its period at
// 107.505 rad/s (test_orbit_continuation.cpp's AStickSlipBranchOnTheBore). The paper's rotor (R_r = 5 C) rolls
// throughout at f = 1: a neutral multiplier (every phase of the rolling is an orbit).
TEST(OrbitsCli, StickingOrbits) {
  const std::string thin = "--scene " + config("stick_slip_rub.yaml") + " --speed 110";
  const Result r = orbits(thin);
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* line : {"stick     at t = 0.01211569", "slip      at t = 0.02635748", "stable",
                           "multipliers on the bore's tangent space, 2 of them", "|mu| 0.43264225"}) {
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  }
  const Result branch = orbits(thin + " --continue 100 120");
  EXPECT_EQ(branch.status, 0) << branch.err;
  EXPECT_NE(branch.out.find("branch 0: period_doubling at 107.5053"), std::string::npos) << branch.out;
  const Result whip = orbits("--scene " + config("horizontal_rub.yaml") +
                             " --set friction_coefficient=1 --set restitution=0 --speed 100");
  ASSERT_EQ(whip.status, 0) << whip.err;
  EXPECT_NE(whip.out.find("neutral"), std::string::npos) << whip.out;
  EXPECT_NE(whip.out.find("sticking (rolling on it: dry whip)"), std::string::npos) << whip.out;
}

// From a run (--from-run, --at): the paper's run-up held at 160 rad/s stays
// in the full rub, an orbit on the bore whose branch turns back at the
// fold where rotor_rub_stability puts it (167.936436 rad/s); the flow from
// rest at the same speed settles without contact (the hysteresis band).
// A time past the run, a run at another speed, --at alone: exit status 2.
TEST(OrbitsCli, FromARun) {
  const std::string run_csv = rotor_rub::test::tmp() + "/runup_160.csv";
  const std::string scene = "--scene " + config("paper_runup.yaml");
  const Result run = rotor_rub::test::run_cli(
      ROTOR_RUB_RUN, scene + " --set target_speed_rad_per_s=160 --set end_time_s=4 --quiet --csv " + run_csv);
  ASSERT_EQ(run.status, 0) << run.err;
  const Result r = orbits(scene + " --speed 160 --from-run " + run_csv + " --at 3.9 --continue 150 200");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* line :
       {"at t = 3.9 s", "on the bore throughout, sliding (the full rub)", "stable", "branch 0: fold at 167.93643"}) {
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  }
  EXPECT_NE(orbits(scene + " --speed 160").out.find("no contact"), std::string::npos);
  for (const auto& [args, part] :
       {std::pair<std::string, std::string>{" --speed 160 --from-run " + run_csv + " --at 5",
                                            "past the run's last sample"},
        {" --speed 150 --from-run " + run_csv + " --at 3.9", "the run's speed at t = 3.9 s is 160 rad/s"},
        {" --speed 160 --at 3.9", "--at needs --from-run"}}) {
    const Result bad = orbits(scene + args);
    EXPECT_EQ(bad.status, 2) << args;
    EXPECT_NE(bad.err.find(part), std::string::npos) << args << ": " << bad.err;
  }
}

// In the turning frame (--turning): the paper's scene run down from 600 to
// 500 rad/s and held settles on a partial rub that repeats in the frame
// turning with the shaft every 3.81 forcing periods (two touchdowns),
// quasi-periodic in the casing (test_turning_orbit.cpp holds the method).
// A scene with gravity, or --turning with --continue: exit status 2.
TEST(OrbitsCli, TurningFrameOrbitFromARunDown) {
  const std::string run_csv = rotor_rub::test::tmp() + "/rundown_500.csv";
  const std::string scene = "--scene " + config("paper_runup.yaml");
  const std::string rundown =
      " --set initial_speed_rad_per_s=600 --set target_speed_rad_per_s=500 --set acceleration_rad_per_s2=500";
  const Result run = rotor_rub::test::run_cli(
      ROTOR_RUB_RUN, scene + rundown + " --set end_time_s=20 --rate 100 --quiet --csv " + run_csv);
  ASSERT_EQ(run.status, 0) << run.err;
  const Result r = orbits(scene + " --speed 500 --from-run " + run_csv + " --at 19 --turning");
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* line :
       {"in the frame turning with the shaft: period T_r = 0.04785325", "(3.80804", "stable", "touchdown at t"}) {
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  }
  const Result gravity = orbits("--scene " + config("horizontal_rub.yaml") + " --speed 60 --turning");
  EXPECT_EQ(gravity.status, 2);
  EXPECT_NE(gravity.err.find("scene key 'gravity_m_per_s2' is 9.81"), std::string::npos) << gravity.err;
  const Result traced = orbits(scene + " --speed 500 --turning --continue 450 550");
  EXPECT_EQ(traced.status, 2);
  EXPECT_NE(traced.err.find("--turning takes no --continue"), std::string::npos) << traced.err;
}

TEST(OrbitsCli, NoOrbitAndBadInput) {
  // Past the Neimark-Sacker point the motion is not periodic: exit 3.
  const Result none = orbits("--scene " + config("horizontal_rub.yaml") + " --speed 66.5");
  EXPECT_EQ(none.status, 3) << none.out;
  EXPECT_NE(none.err.find("no periodic orbit near the guess"), std::string::npos) << none.err;
  for (const auto& [args, part] :
       {std::pair<std::string, std::string>{
            "--scene " + config("horizontal_rub.yaml") + " --speed 60 --set method=penalty",
            "scene key 'method' is 'penalty'"},
        {"--scene " + config("horizontal_rub.yaml") + " --speed 60 --set drive_model=motor",
         "scene key 'drive_model' is 'motor'"},
        {"--scene " + config("seal_rub_runup.yaml") + " --speed 100", "the Jeffcott rotor only"},
        {"--scene " + config("horizontal_rub.yaml") + " --speed 60 --continue 61 70", "LO < start < HI"},
        {"--scene " + config("horizontal_rub.yaml") + " --speed 60 --continue 0 1 --parameter rtol",
         "--parameter 'rtol': not a number of the model"},
        {"--scene " + config("horizontal_rub.yaml") + " --speed 60 --continue 0 1 --parameter frction_coefficient",
         "did you mean 'friction_coefficient'"},
        {"--scene " + config("horizontal_rub.yaml") + " --speed 60 --set restitutoin=0.2",
         "did you mean 'restitution'"}}) {
    const Result r = orbits(args);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_NE(r.err.find(part), std::string::npos) << args << ": " << r.err;
  }
}
