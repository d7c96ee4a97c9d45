// Runs a command-line tool for the CLI tests: its exit status (-1 when a
// signal ended it: a crash) and what it wrote on stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>

namespace rotor_rub::test {

struct CliResult {
  int status;
  std::string err;
  std::string out;
};

// `prefix` goes before the command in the shell: "cd /tmp &&", "env -u VAR".
inline CliResult run_cli(const std::string& binary, const std::string& args, const std::string& prefix = "") {
  const std::string base = "/tmp/rotor_rub_cli." + std::to_string(::getpid());
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

}  // namespace rotor_rub::test
