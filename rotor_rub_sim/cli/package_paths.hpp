// Finds the files the package ships (config/paper_runup.yaml, say) from any
// directory, in a devel space and in an install space alike.
#pragma once

#include <string>
#include <vector>

namespace rotor_rub::cli {

// Where `relative` (a path inside the package, e.g. "config/paper_runup.yaml")
// may be, in the order they are tried:
//  1. beside the executable: <prefix>/lib/rotor_rub_sim/<tool> ->
//     <prefix>/share/rotor_rub_sim/<relative> (an install space);
//  2. each ROS_PACKAGE_PATH entry E: E/rotor_rub_sim/<relative>, and
//     E/<relative> when E itself is the package (its package.xml names it);
//  3. the source directory the tools were built from (a devel space).
std::vector<std::string> package_file_candidates(const std::string& relative);

// The first candidate that exists. Throws std::runtime_error naming every
// path tried when none does.
std::string find_package_file(const std::string& relative);

}  // namespace rotor_rub::cli
