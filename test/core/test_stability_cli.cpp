// rotor_rub_stability's command line: the paper scene's branches, folds and
// their CSV, a rigid stator's change of stability, and bad input as one line
// with exit status 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "temp_dir.hpp"

namespace {

using Result = rotor_rub::test::CliResult;

Result stability(const std::string& args) { return rotor_rub::test::run_cli(ROTOR_RUB_STABILITY, args); }

std::string config(const std::string& name) { return std::string(ROTOR_RUB_SOURCE_DIR) + "/config/" + name; }

}  // namespace

// The paper scene (elastic stator, f = 0.1): two branches up to the fold at
// 167.936436 rad/s, none to 224.043009, the upper stable below the fold,
// unstable beyond the gap (FullRubStability's figures); one CSV row per
// branch and speed.
TEST(StabilityCli, PaperSceneFoldsAndItsCsv) {
  const std::string csv = rotor_rub::test::tmp() + "/branches.csv";
  const Result r = stability("--scene " + config("paper_runup.yaml") + " --speeds 100 300 --points 11 --csv " + csv);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("fold at 167.936436 rad/s: 2 branches below, 0 above"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("fold at 224.043009 rad/s: 0 branches below, 2 above"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("   120.0000       0        10.52    0.0024088       -3.2028        304.73  yes"),
            std::string::npos)
      << r.out;
  std::ifstream in(csv);
  std::string line;
  int rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 1 + 2 * 8);  // the header; two branches at 100..160 and 240..300
}

// A rigid stator at f = 0.1 (--set): its upper branch is stable everywhere it
// exists, so no change of stability is reported; an anisotropic flexible
// rotor (the seal-rub example), a motor, a reversed range are refused.
TEST(StabilityCli, RigidStatorAndBadInput) {
  const Result r =
      stability("--scene " + config("paper_runup.yaml") + " --set stator_model=rigid --speeds 100 600 --points 6");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.find("turns"), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 2 + 2 * 6) << r.out;  // two branches at every speed
  for (const auto& [args, part] :
       {std::pair<std::string, std::string>{"--scene " + config("seal_rub_runup.yaml") + " --speeds 100 300",
                                            "not isotropic"},
        {"--scene " + config("machine_runup.yaml") + " --speeds 100 300", "the prescribed drive only"},
        {"--scene " + config("paper_runup.yaml") + " --speeds 300 100", "--speeds needs LO < HI"},
        {"--scene " + config("paper_runup.yaml") + " --speeds 100 300 --set friction_coefficent=0.2",
         "did you mean 'friction_coefficient'"}}) {
    const Result bad = stability(args);
    EXPECT_EQ(bad.status, 2) << args << "\n" << bad.out;
    EXPECT_EQ(std::count(bad.err.begin(), bad.err.end(), '\n'), 1) << bad.err;
    EXPECT_NE(bad.err.find(part), std::string::npos) << bad.err;
  }
}

// An isotropic flexible rotor, reduced as the scene's runs reduce it: the
// seal rotor's full rub at 300 rad/s (rigid seal, 20 um, f = 0.1) holds
// with 8 planar modes and flutters with 12 (FullRubStability's figures).
TEST(StabilityCli, TheSealRotorAtEightAndTwelveModes) {
  const std::string rotor = std::string(ROTOR_RUB_SOURCE_DIR) + "/test/data/rotors/isotropic_seal.yaml";
  for (const auto& [modes, verdict] : {std::pair<int, std::string>{8, "yes"}, {12, "no"}}) {
    const Result r = stability("--scene " + config("seal_rub_runup.yaml") + " --set rotor_file=" + rotor +
                               " --set rotor_planar_modes=" + std::to_string(modes) +
                               " --set friction_coefficient=0.1 --speeds 299 300 --points 2");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find(std::to_string(modes) + " planar modes"), std::string::npos) << r.out;
    const std::string last = r.out.substr(r.out.find("   300.0000       0"));
    EXPECT_NE(last.find(verdict), std::string::npos) << modes << ": " << last;
  }
  // Below 185.37 rad/s the free orbit stays inside the seal: the one branch
  // begins where its normal force passes 0, which is no fold; traced by
  // continuation from there up, stable with 8 modes.
  const std::string csv = rotor_rub::test::tmp() + "/seal_branch.csv";
  const Result r = stability("--scene " + config("seal_rub_runup.yaml") + " --set rotor_file=" + rotor +
                             " --set rotor_planar_modes=8 --set friction_coefficient=0.1 --speeds 150 250 --points 3"
                             " --branch-csv " +
                             csv);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("a branch's normal force passes 0 (the free orbit touches the bore) at 185.366898 rad/s: 0 "
                       "branches below, 1 above"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("fold"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("continuation from 200 rad/s"), std::string::npos) << r.out;
}

// --branch-csv: the paper scene's upper branch traced by continuation from
// 100 rad/s through its fold (where the grid's bisection puts it too) and
// back along the lower, unstable branch, its points in the CSV in the order
// traced: the speed rises to the fold and falls after it.
TEST(StabilityCli, TheBranchByContinuationPassesItsFold) {
  const std::string csv = rotor_rub::test::tmp() + "/branch.csv";
  const Result r =
      stability("--scene " + config("paper_runup.yaml") + " --speeds 100 300 --points 11 --branch-csv " + csv);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("continuation: fold at 167.936436"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("continuation: stability changes at 167.936436"), std::string::npos) << r.out;
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line,
            "speed_rad_per_s,normal_force_N,rotor_orbit_m,stator_orbit_m,growth_rate_per_s,"
            "frequency_rad_per_s,stable");
  std::vector<double> speeds;
  std::vector<int> stable;
  while (std::getline(in, line)) {
    speeds.push_back(std::stod(line));
    stable.push_back(line.back() - '0');
  }
  ASSERT_GT(speeds.size(), 10u);
  const auto top = std::max_element(speeds.begin(), speeds.end());
  // The highest traced point lies just below the fold, never past it: the
  // tangent may turn by 18 deg a step, which keeps the steps short where the
  // branch turns back (measured: 1.5e-6 rad/s below it).
  constexpr double kFold_rad_per_s = 167.936436359;  // printed to 1e-9
  constexpr double kPrinted_rad_per_s = 1e-9, kNearFold_rad_per_s = 1e-2;
  EXPECT_NEAR(*top, kFold_rad_per_s, kNearFold_rad_per_s);
  EXPECT_LE(*top, kFold_rad_per_s + kPrinted_rad_per_s);
  EXPECT_TRUE(std::is_sorted(speeds.begin(), top));
  EXPECT_TRUE(std::is_sorted(speeds.rbegin(), std::make_reverse_iterator(top + 1)));
  EXPECT_EQ(stable.front(), 1);
  EXPECT_EQ(stable.back(), 0);
}
