// The scene's messages' numbers (scene_keys.cpp, scene_validation.cpp): 15
// significant digits, as the key table's ranges print. Not installed.
#pragma once

#include <sstream>
#include <string>

namespace rotor_rub::core {

inline std::string format_double(double v) {
  std::ostringstream os;
  os.precision(15);
  os << v;
  return os.str();
}

}  // namespace rotor_rub::core
