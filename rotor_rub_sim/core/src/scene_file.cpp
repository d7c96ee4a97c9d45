#include "rotor_rub_sim/core/scene_file.hpp"

#include <fstream>

#include "rotor_rub_sim/core/scene_keys.hpp"

namespace rotor_rub::core {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::string strip_comment(const std::string& line) {
  // A '#' starts a comment at the line start or after whitespace (YAML).
  for (std::size_t i = 0; i < line.size(); ++i) {
    if (line[i] == '#' && (i == 0 || line[i - 1] == ' ' || line[i - 1] == '\t')) return line.substr(0, i);
  }
  return line;
}

}  // namespace

std::map<std::string, std::string> read_scene_values(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw SceneError("scene file '" + path + "' cannot be opened");
  std::map<std::string, std::string> values;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string where = path + ":" + std::to_string(number);
    if (line.find('\t') == 0 || (!line.empty() && line[0] == ' ' && !trim(strip_comment(line)).empty())) {
      throw SceneError(where + ": nested YAML is not a scene; keys are flat (key: value)");
    }
    const std::string content = trim(strip_comment(line));
    if (content.empty() || content == "---") continue;
    const auto colon = content.find(':');
    if (colon == std::string::npos) throw SceneError(where + ": expected 'key: value', got '" + content + "'");
    const std::string key = trim(content.substr(0, colon));
    std::string value = trim(content.substr(colon + 1));
    if (value.size() >= 2 && (value.front() == '"' || value.front() == '\'') && value.back() == value.front()) {
      value = value.substr(1, value.size() - 2);
    }
    if (value.empty()) throw SceneError(where + ": scene key '" + key + "' has no value");
    if (values.count(key)) throw SceneError(where + ": scene key '" + key + "' given twice");
    values[key] = value;
  }
  return values;
}

Scene load_scene(const std::string& path, const std::map<std::string, std::string>& overrides) {
  std::map<std::string, std::string> values = read_scene_values(path);
  for (const auto& [k, v] : overrides) values[k] = v;
  return scene_from_values(values);
}

}  // namespace rotor_rub::core
