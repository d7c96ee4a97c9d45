// Rotor files written for a test, and the error a bad one gets (the reader's
// or assemble()'s), shared by the suites that read rotor files.
#pragma once

#include <fstream>
#include <stdexcept>
#include <string>

#include "rotor_rub_sim/core/fe_rotor.hpp"
#include "rotor_rub_sim/core/rotor_file.hpp"
#include "temp_dir.hpp"

namespace rotor_rub::test {

// Writes text to the test's own directory; returns the path.
inline std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = tmp() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// The message a rotor file of this text is refused with, or "accepted".
inline std::string load_error(const std::string& text) {
  try {
    core::assemble(core::load_rotor_file(write_file("bad_rotor.yaml", text)));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "accepted";
}

}  // namespace rotor_rub::test
