#include "cli_options.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "rotor_rub_sim/core/scene_keys.hpp"

namespace rotor_rub::cli {
namespace {

std::string format_double(double v) {  // as the scene keys print their ranges
  std::ostringstream os;
  os.precision(15);
  os << v;
  return os.str();
}

// The whole text a finite number (surrounding blanks allowed); false if not.
bool parse_number(const std::string& text, double& v) {
  const char* begin = text.c_str();
  char* end = nullptr;
  v = std::strtod(begin, &end);
  if (end == begin) return false;
  while (*end == ' ' || *end == '\t') ++end;
  return *end == '\0';
}

const core::SceneKeyInfo& key_info(const std::string& key) {
  for (const auto& k : core::scene_keys()) {
    if (k.key == key) return k;
  }
  throw std::logic_error("no scene key '" + key + "'");
}

}  // namespace

CLI::Validator number_in(double lo, double hi, bool lo_open) {
  const std::string accepted = std::string(lo_open ? "(" : "[") + format_double(lo) + ", " + format_double(hi) + "]";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0.0;
        if (!parse_number(text, v)) return "value '" + text + "' is not a number; accepted: " + accepted;
        if (!std::isfinite(v)) return "value '" + text + "' is not a finite number; accepted: " + accepted;
        if ((lo_open ? !(v > lo) : !(v >= lo)) || v > hi) {
          return "value " + text + " is out of range; accepted: " + accepted;
        }
        return std::string();
      },
      "number in " + accepted, "number_in");
}

CLI::Validator integer_in(long lo, long hi) {
  const std::string accepted = "integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0.0;
        if (!parse_number(text, v) || !std::isfinite(v) || v != std::floor(v)) {
          return "value '" + text + "' is not an integer; accepted: " + accepted;
        }
        if (v < static_cast<double>(lo) || v > static_cast<double>(hi)) {
          return "value " + text + " is out of range; accepted: " + accepted;
        }
        // The integer conversion after this wants digits only ("1e3" is 1000).
        text = std::to_string(static_cast<long>(v));
        return std::string();
      },
      accepted, "integer_in");
}

CLI::Validator key_value() {
  return CLI::Validator(
      [](std::string& kv) -> std::string {
        const auto eq = kv.find('=');
        if (eq == std::string::npos || eq == 0) return "value '" + kv + "' is not accepted; accepted: key=value";
        rotor_rub::core::Scene scratch;
        try {
          rotor_rub::core::set_scene_value(scratch, kv.substr(0, eq), kv.substr(eq + 1));
        } catch (const rotor_rub::core::SceneError& e) {
          return e.what();
        }
        return std::string();
      },
      "", "key_value");
}

void add_scene_options(CLI::App& app, std::string& path, std::vector<std::string>& sets,
                       const std::string& scene_description, const std::string& set_description) {
  app.add_option("--scene", path, scene_description)->type_name("FILE")->check(existing_file());
  app.add_option("--set", sets, set_description)->type_name("KEY=VALUE")->allow_extra_args(false)->check(key_value());
}

std::map<std::string, std::string> scene_overrides(const std::vector<std::string>& sets) {
  std::map<std::string, std::string> overrides;
  for (const std::string& kv : sets) {
    const auto eq = kv.find('=');  // key_value() checked there is one
    overrides[kv.substr(0, eq)] = kv.substr(eq + 1);
  }
  return overrides;
}

CLI::Validator scene_key(const std::string& key) {
  const core::SceneKeyInfo& info = key_info(key);
  return CLI::Validator(
      [key](std::string& text) -> std::string {
        core::Scene scratch;
        try {
          core::set_scene_value(scratch, key, text);
        } catch (const core::SceneError& e) {
          return e.what();
        }
        return std::string();
      },
      info.accepted, "scene_key");
}

std::string scene_key_description(const std::string& key) {
  const core::SceneKeyInfo& info = key_info(key);
  // The key's default, not the scene file's value: what a scene without the key runs.
  return info.description + "; sets scene key " + key + " (the key's default: " + info.default_value + ")";
}

CLI::Validator existing_file() { return CLI::Validator(CLI::ExistingFile).description(""); }

void usage_error(const CLI::App& app, const std::string& message) {
  std::cerr << app.get_name() << ": " << message << " (see " << app.get_name() << " --help)\n";
  std::exit(kExitUsage);
}

void parse_or_exit(CLI::App& app, int argc, const char* const* argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    std::exit(0);
  } catch (const CLI::ExtrasError&) {
    // CLI11 says "The following argument was not expected"; name it as ours do.
    std::string what;
    for (const auto& a : app.remaining()) {
      what += (what.empty() ? "" : ", ") +
              std::string(!a.empty() && a[0] == '-' ? "unknown option '" : "unexpected argument '") + a + "'";
    }
    usage_error(app, what.empty() ? std::string("unexpected arguments") : what);
  } catch (const CLI::ParseError& e) {
    usage_error(app, e.what());
  }
}

CLI::Validator shard_spec() {
  return CLI::Validator(
      [](std::string& s) -> std::string {
        unsigned si = 0, sn = 0;
        char extra = 0;
        if (std::sscanf(s.c_str(), "%u/%u%c", &si, &sn, &extra) != 2 || sn == 0 || si >= sn) {
          return "value '" + s + "' is not accepted; accepted: I/N with 0 <= I < N";
        }
        return std::string();
      },
      "", "shard");
}

}  // namespace rotor_rub::cli
