#include "package_paths.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rotor_rub::cli {
namespace {

constexpr const char* kPackage = "rotor_rub_sim";

std::string self_executable() {
  char buf[4096];
  const ssize_t n = ::readlink("/proc/self/exe", buf, sizeof buf - 1);
  return n > 0 ? std::string(buf, static_cast<std::size_t>(n)) : std::string();
}

std::string dirname(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : slash == 0 ? std::string("/") : path.substr(0, slash);
}

bool is_file(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}

// Whether dir/package.xml declares this package.
bool is_our_package(const std::string& dir) {
  std::ifstream f(dir + "/package.xml");
  if (!f) return false;
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str().find(std::string("<name>") + kPackage + "</name>") != std::string::npos;
}

}  // namespace

std::vector<std::string> package_file_candidates(const std::string& relative) {
  std::vector<std::string> out;
  const std::string exe = self_executable();
  if (!exe.empty()) {
    // <prefix>/lib/rotor_rub_sim/<tool>: two levels up is the prefix.
    out.push_back(dirname(dirname(dirname(exe))) + "/share/" + kPackage + "/" + relative);
  }
  if (const char* rpp = std::getenv("ROS_PACKAGE_PATH")) {
    std::stringstream entries(rpp);
    for (std::string e; std::getline(entries, e, ':');) {
      if (e.empty()) continue;
      while (e.size() > 1 && e.back() == '/') e.pop_back();
      out.push_back(e + "/" + kPackage + "/" + relative);
      if (is_our_package(e)) out.push_back(e + "/" + relative);
    }
  }
#ifdef ROTOR_RUB_SOURCE_DIR
  out.push_back(std::string(ROTOR_RUB_SOURCE_DIR) + "/" + relative);
#endif
  return out;
}

std::string find_package_file(const std::string& relative) {
  const auto candidates = package_file_candidates(relative);
  for (const auto& c : candidates) {
    if (is_file(c)) return c;
  }
  std::string tried;
  for (const auto& c : candidates) tried += (tried.empty() ? "" : ", ") + c;
  throw std::runtime_error(std::string("package ") + kPackage + ": " + relative +
                           " not found (tried: " + (tried.empty() ? "no path" : tried) + ")");
}

}  // namespace rotor_rub::cli
