#include "rotor_rub_sim/core/scene_file.hpp"

#include <filesystem>

#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/yaml_values.hpp"

namespace rotor_rub::core {

std::map<std::string, std::string> read_scene_values(const std::string& path) {
  std::vector<YamlDocument> docs;
  try {
    docs = read_yaml_documents(path);
  } catch (const YamlError& e) {
    throw SceneError(std::string("scene file ") + e.what());
  }
  // Documents of comments only (a trailing "---", say) hold nothing.
  std::vector<YamlDocument> filled;
  for (auto& d : docs) {
    if (!d.empty()) filled.push_back(std::move(d));
  }
  if (filled.size() > 1) {
    throw SceneError("scene file '" + path + "' holds " + std::to_string(filled.size()) +
                     " YAML documents; accepted: one mapping of scene keys");
  }
  if (filled.empty()) filled.emplace_back();
  docs.swap(filled);
  std::map<std::string, std::string> values;
  // Every value is checked on its own here, also one that an override will
  // replace: a bad file is an error whatever the command line says.
  Scene scratch;
  for (const YamlEntry& e : docs.front()) {
    if (e.is_list) {
      throw SceneError(e.where + ": scene key '" + e.key + "' has a list as its value; accepted: a scalar " +
                       "(lists of values belong in a sweep grid)");
    }
    try {
      set_scene_value(scratch, e.key, e.values.front());
    } catch (const SceneError& err) {
      throw SceneError(e.where + ": " + err.what());
    }
    values[e.key] = e.values.front();
    // A rotor file is named relative to the scene file that names it.
    if (e.key == "rotor_file" && !e.values.front().empty() && std::filesystem::path(e.values.front()).is_relative()) {
      values[e.key] = (std::filesystem::path(path).parent_path() / e.values.front()).lexically_normal().string();
    }
  }
  return values;
}

Scene load_scene(const std::string& path, const std::map<std::string, std::string>& overrides) {
  std::map<std::string, std::string> values = read_scene_values(path);
  for (const auto& [k, v] : overrides) values[k] = v;
  return scene_from_values(values);
}

}  // namespace rotor_rub::core
