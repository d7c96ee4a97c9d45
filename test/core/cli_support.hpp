// Runs a command-line tool for the CLI tests: its exit status (-1 when a
// signal ended it: a crash) and what it wrote on stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "temp_dir.hpp"

namespace rotor_rub::test {

struct CliResult {
  int status;
  std::string err;
  std::string out;
};

// `prefix` goes before the command in the shell: "cd DIR &&", "env -u VAR".
inline CliResult run_cli(const std::string& binary, const std::string& args, const std::string& prefix = "") {
  const std::string base = rotor_rub::test::tmp() + "cli";
  const int rc = std::system((prefix + " " + binary + " " + args + " > " + base + ".out 2> " + base + ".err").c_str());
  auto slurp = [](const std::string& path) {
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
  };
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, slurp(base + ".err"), slurp(base + ".out")};
}

// Whether every option is named in a tool's --help.
inline std::string missing_options(const std::string& help, std::initializer_list<const char*> options) {
  std::string missing;
  for (const char* o : options) {
    if (help.find(o) == std::string::npos) missing += std::string(" ") + o;
  }
  return missing;
}

using Row = std::map<std::string, std::string>;

// A CSV reader for this table: quoted fields hold no newlines.
inline std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  bool q = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (q) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cur += '"';
        ++i;
      } else if (c == '"') {
        q = false;
      } else {
        cur += c;
      }
    } else if (c == '"') {
      q = true;
    } else if (c == ',') {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

inline std::vector<Row> read_rows(const std::string& path) {
  std::ifstream f(path);
  std::string line;
  std::getline(f, line);
  const auto header = split(line);
  std::vector<Row> rows;
  while (std::getline(f, line)) {
    const auto cells = split(line);
    if (cells.size() != header.size())
      throw std::runtime_error("'" + path + "': a row of " + std::to_string(cells.size()) + " cells under " +
                               std::to_string(header.size()) + " columns: " + line);
    Row r;
    for (std::size_t i = 0; i < header.size() && i < cells.size(); ++i) r[header[i]] = cells[i];
    rows.push_back(r);
  }
  return rows;
}

}  // namespace rotor_rub::test
