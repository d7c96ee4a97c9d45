// rotor_rub_modal's command line: ROSS's example's frequencies, the modal
// truncation study at a rub station (its table, exact with every mode, the
// recommendation), the CSVs, and bad input as one line with exit status 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "temp_dir.hpp"

namespace {

using Result = rotor_rub::test::CliResult;

Result modal(const std::string& args) { return rotor_rub::test::run_cli(ROTOR_RUB_MODAL, args); }

std::string rotor(const std::string& name) { return std::string(ROTOR_RUB_SOURCE_DIR) + "/config/rotors/" + name; }

void expect_bad_input(const Result& r, const std::string& part) {
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(part), std::string::npos) << r.err;
}

}  // namespace

TEST(ModalCli, RossExampleAndItsCsvs) {
  const std::string dir = rotor_rub::test::tmp();
  const Result r =
      modal("--rotor " + rotor("ross_example.yaml") + " --modes 4 --max-speed 400 --speeds 5 --campbell " + dir +
            "/campbell.csv --unbalance-node 2 --unbalance-kg-m 1e-4 --response " + dir + "/response.csv");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("91.79655318"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("96.28899977"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("critical speeds"), std::string::npos) << r.out;  // on request
  EXPECT_EQ(r.out.find("overdamped"), std::string::npos) << r.out;       // it has none
  // The critical speeds ROSS's example has below 400 rad/s (rotors.md), bracketed on 5 speeds.
  const Result c = modal("--rotor " + rotor("ross_example.yaml") +
                         " --modes 4 --max-speed 400 --speeds 5 "
                         "--critical-speeds");
  ASSERT_EQ(c.status, 0) << c.err;
  for (const char* line :
       {"mode 0: 91.788309 rad/s", "mode 1: 96.295529 rad/s", "mode 2: 271.251887 rad/s", "mode 3: 300.351513 rad/s"}) {
    EXPECT_NE(c.out.find(line), std::string::npos) << line << "\n" << c.out;
  }
  std::ifstream campbell(dir + "/campbell.csv"), response(dir + "/response.csv");
  std::string line;
  int rows = 0;
  while (std::getline(campbell, line)) ++rows;
  EXPECT_EQ(rows, 1 + 5 * 4);  // header, 5 speeds x 4 modes
  rows = 0;
  while (std::getline(response, line)) ++rows;
  EXPECT_EQ(rows, 1 + 4);  // header, the speeds above 0
}

// The shapes CSV (every node of every mode, the largest entry 1) and the
// pictures scripts/plot_campbell.py draws from the three CSVs.
TEST(ModalCli, ShapesAndPictures) {
  const std::string dir = rotor_rub::test::tmp();
  const Result r =
      modal("--rotor " + rotor("ross_example.yaml") + " --modes 3 --max-speed 400 --speeds 5 --campbell " + dir +
            "/c.csv --unbalance-node 2 --unbalance-kg-m 1e-4 --response " + dir + "/r.csv --shapes " + dir + "/s.csv");
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream shapes(dir + "/s.csv");
  std::string line;
  std::getline(shapes, line);
  EXPECT_EQ(line.rfind("mode,node,z_m,x_re,x_im,y_re,y_im", 0), 0u) << line;
  int rows = 0;
  double last_z = 0.0;
  while (std::getline(shapes, line)) {
    ++rows;
    last_z = std::stod(line.substr(line.find(',', line.find(',') + 1) + 1));
  }
  EXPECT_EQ(rows, 3 * 7);           // 3 modes x 7 nodes
  EXPECT_NEAR(last_z, 1.5, 1e-12);  // 6 elements of 0.25 m
  const std::string plot = std::string("/usr/bin/python3 ") + ROTOR_RUB_SOURCE_DIR + "/scripts/plot_campbell.py ";
  const Result p = rotor_rub::test::run_cli(
      plot, dir + "/c.csv --response " + dir + "/r.csv --shapes " + dir + "/s.csv --out " + dir + "/pictures");
  ASSERT_EQ(p.status, 0) << p.err;
  for (const char* png : {"campbell.png", "response.png", "shapes.png"}) {
    std::ifstream f(dir + "/pictures/" + png, std::ios::binary);
    char magic[4] = {};
    f.read(magic, 4);
    EXPECT_EQ(std::string(magic + 1, 3), "PNG") << png;
  }
  // A CSV that is not the tool's: one line, status 2.
  const Result bad = rotor_rub::test::run_cli(plot, dir + "/r.csv --out " + dir + "/pictures");
  EXPECT_EQ(bad.status, 2) << bad.err;
  EXPECT_NE(bad.err.find("lacks the columns"), std::string::npos) << bad.err;
}

// The study's rows: 1, 2, 4, 8, 16 and all 26 planar modes of the seal rotor;
// the last is the full model (errors at roundoff), the errors fall, and the
// recommendation is the first row within the tolerance.
TEST(ModalCli, TruncationStudyAtTheRubStation) {
  const Result r = modal("--rotor " + rotor("seal_rub.yaml") +
                         " --modes 2 --max-speed 500 --speeds 21 --station 6 --unbalance-node 3 --unbalance-kg-m 1e-4 "
                         "--tolerance 1e-2");
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream out(r.out.substr(r.out.find("planar modes  coordinates")));
  std::string line;
  std::getline(out, line);  // the header
  std::vector<int> modes;
  std::vector<double> worst;
  while (std::getline(out, line) && line.find("smallest") == std::string::npos) {
    std::istringstream row(line);
    int m = 0, coordinates = 0;
    double mass = 0, frequency = 0, response = 0;
    row >> m >> coordinates >> mass >> frequency >> response;
    ASSERT_TRUE(row) << line;
    EXPECT_EQ(coordinates, 2 * m);
    modes.push_back(m);
    worst.push_back(std::max(frequency, response));
  }
  EXPECT_EQ(modes, (std::vector<int>{1, 2, 4, 8, 16, 26}));
  ASSERT_EQ(worst.size(), 6u);
  EXPECT_LT(worst.back(), 1e-9);
  for (std::size_t k = 2; k < worst.size(); ++k) EXPECT_LT(worst[k], worst[k - 1]) << modes[k];
  std::size_t first = 0;
  while (first + 1 < worst.size() && worst[first] > 1e-2) ++first;
  EXPECT_NE(line.find("smallest model within 0.01: " + std::to_string(modes[first]) + " planar modes"),
            std::string::npos)
      << line;
}

// --export-matrices writes the assembled rotor as matrices by their nonzeros
// in 17 digits, with its stations: read back, every output is the element
// file's to the last digit (the seal-rub rotor: cross-coupled seal, two
// unbalances, probes, a rub station: the study uses them all), and the
// file holds far fewer numbers than the dense rows would.
TEST(ModalCli, ExportedMatricesAreTheRotor) {
  const std::string dir = rotor_rub::test::tmp();
  const std::string args = " --modes 8 --max-speed 500 --speeds 6 --critical-speeds --study";
  const Result elements = modal("--rotor " + rotor("seal_rub.yaml") + args + " --export-matrices " + dir + "/m.yaml");
  ASSERT_EQ(elements.status, 0) << elements.err;
  EXPECT_NE(elements.out.find("wrote " + dir + "/m.yaml"), std::string::npos) << elements.out;
  const Result matrices = modal("--rotor " + dir + "/m.yaml" + args);
  ASSERT_EQ(matrices.status, 0) << matrices.err;
  EXPECT_NE(matrices.out.find("13 nodes, imported matrices, 52 DOF (read in "), std::string::npos) << matrices.out;
  auto after_header = [](const std::string& out) { return out.substr(out.find("at rest:")); };
  auto without_export_line = [](std::string out) {
    const std::size_t at = out.find("wrote ");
    return at == std::string::npos ? out : out.erase(at, out.find('\n', at) + 1 - at);
  };
  EXPECT_EQ(after_header(matrices.out), after_header(without_export_line(elements.out)));
  std::ifstream file(dir + "/m.yaml");
  std::string line;
  int entries = 0;
  while (std::getline(file, line)) entries += line.rfind("      - [", 0) == 0;
  EXPECT_GT(entries, 52);
  EXPECT_LT(entries, 4 * 52 * 52 / 4);  // banded: under a quarter of the dense entries
}

TEST(ModalCli, BadInputIsOneLineWithStatus2) {
  expect_bad_input(modal("--rotor " + rotor("seal_rub.yaml") + " --modes 2 --max-speed 100 --station 13"),
                   "node 13 is out of range; accepted: 0 to 12");
  expect_bad_input(
      modal("--rotor " + rotor("seal_rub.yaml") + " --modes 2 --max-speed 100 --station 6 --probe-nodes 40"),
      "probe node 40 is out of range");
  expect_bad_input(modal("--rotor " + rotor("seal_rub.yaml") + " --tolerance 2"), "--tolerance");
  expect_bad_input(modal("--rotor " + rotor("ross_example.yaml") + " --modes 2 --study"),
                   "--study needs a rub station");
  expect_bad_input(modal("--rotor " + rotor("ross_example.yaml") + " --jobs 0"), "--jobs");
}

// --jobs solves speeds at once: the Campbell diagram and the critical speeds
// the same, byte for byte, at one job and at three.
TEST(ModalCli, JobsChangeNothingButTheTime) {
  const std::string dir = rotor_rub::test::tmp();
  std::string csv[2], out[2];
  for (int i = 0; i < 2; ++i) {
    const std::string jobs = i == 0 ? "1" : "3";
    const Result r = modal("--rotor " + rotor("ross_example.yaml") +
                           " --modes 4 --max-speed 400 --speeds 9 --critical-speeds --jobs " + jobs + " --campbell " +
                           dir + "/campbell_" + jobs + ".csv");
    ASSERT_EQ(r.status, 0) << r.err;
    out[i] = r.out.substr(r.out.find('\n') + 1);  // after the first line's read time
    std::ifstream f(dir + "/campbell_" + jobs + ".csv");
    std::stringstream text;
    text << f.rdbuf();
    csv[i] = text.str();
  }
  EXPECT_NE(out[0].find("mode 3: 300.351513 rad/s"), std::string::npos) << out[0];
  EXPECT_EQ(out[1], out[0]);
  EXPECT_EQ(std::count(csv[0].begin(), csv[0].end(), '\n'), 1 + 9 * 4);
  EXPECT_EQ(csv[1], csv[0]);
}
