// Reads a scene file: a flat YAML mapping of scene keys to scalars, the same
// file a launch file hands to rosparam. Only the flat subset of YAML is
// accepted (`key: value`, comments, blank lines), so the file means the same
// to every reader.
#pragma once

#include <map>
#include <string>

#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

// key -> value text. Throws SceneError naming the file and line.
std::map<std::string, std::string> read_scene_values(const std::string& path);

// Defaults, then the file, then the overrides (key=value); validated.
Scene load_scene(const std::string& path, const std::map<std::string, std::string>& overrides = {});

}  // namespace rotor_rub::core
