// A directory of this test process's own under gtest's TempDir() (TEST_TMPDIR,
// else /tmp), so two runs of the suites at once never share a file.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace rotor_rub::test {

// "<TempDir>rotor_rub_test.<pid>/", made on first use.
inline const std::string& tmp() {
  static const std::string dir = [] {
    const std::string d = testing::TempDir() + "rotor_rub_test." + std::to_string(::getpid()) + "/";
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

}  // namespace rotor_rub::test
