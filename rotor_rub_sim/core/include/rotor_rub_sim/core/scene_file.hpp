/// @file
/// Reads a scene file: one YAML mapping of scene keys to scalars, the same file
/// a launch file hands to rosparam, read with the meaning rosparam gives it
/// (yaml_values.hpp: any YAML, flow mappings, anchors and quotes included).
#pragma once

#include <map>
#include <string>

#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

/// key -> value text, each value already checked against its key's range (so a
/// bad value is an error even where an override replaces it). A relative
/// rotor_file is the scene file's directory's. Throws SceneError naming the
/// file, line and column.
std::map<std::string, std::string> read_scene_values(const std::string& path);

/// Defaults, then the file, then the overrides (key=value); validated.
Scene load_scene(const std::string& path, const std::map<std::string, std::string>& overrides = {});

}  // namespace rotor_rub::core
