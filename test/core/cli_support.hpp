// Runs a command-line tool for the CLI tests: its exit status (-1 when a
// signal ended it: a crash) and what it wrote on stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace rotor_rub::test {

struct CliResult {
  int status;
  std::string err;
};

inline CliResult run_cli(const std::string& binary, const std::string& args) {
  const std::string err_path = "/tmp/rotor_rub_cli_err." + std::to_string(::getpid()) + ".txt";
  const int rc = std::system((binary + " " + args + " > /dev/null 2> " + err_path).c_str());
  std::ifstream f(err_path);
  std::stringstream ss;
  ss << f.rdbuf();
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, ss.str()};
}

}  // namespace rotor_rub::test
