/// @file
/// The scene's parameter table: every key a scene file, `--set key=value` or a
/// rosparam may set, with its accepted range. One table, used by the YAML
/// loader, the runner and the node, so every entry point validates alike.
#pragma once

#include <cstdint>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

/// A bad scene value: the message names the key, the value and the range;
/// key() and kind() say which key and what is wrong where a caller acts on
/// it (the node's hint at a parameter left on the master), so that no
/// caller reads the message's text.
class SceneError : public std::invalid_argument {
 public:
  /// What is wrong, as far as a caller needs to tell.
  enum class Kind : uint8_t {
    kInvalid,     ///< a value out of range, a rule between keys broken, a refused change
    kUnknownKey,  ///< no such key
  };
  /// what: the message; key: the key it concerns ("" where none or several).
  explicit SceneError(const std::string& what, std::string key = "", Kind kind = Kind::kInvalid)
      : std::invalid_argument(what), key_(std::move(key)), kind_(kind) {}
  const std::string& key() const { return key_; }  ///< the key concerned, or ""
  Kind kind() const { return kind_; }              ///< see Kind

 private:
  std::string key_;
  Kind kind_;
};

/// One scene key as the key table describes it (scene_keys(): --help,
/// --list-keys, the template, docs/node.md).
struct SceneKeyInfo {
  std::string key;            ///< the key as scene files and rosparams name it
  std::string accepted;       ///< human-readable accepted range or names
  std::string description;    ///< one line, with the unit
  std::string default_value;  ///< the default as text (as scene_values writes it)
  /// A number's accepted bounds (the open or closed ends `accepted` states;
  /// +-infinity where unbounded); NaN for a choice of names.
  double min_value = std::numeric_limits<double>::quiet_NaN();
  double max_value = std::numeric_limits<double>::quiet_NaN();  ///< see min_value
  bool is_integer = false;                                      ///< a whole number (step counts, seeds, modes)
  /// May change while a run goes on (Simulation::change_parameters); otherwise
  /// live_refusal says why not.
  bool live = false;
  std::string live_refusal;  ///< why a key that is not live cannot change while a run goes on
};

/// The shortest text that reads back as the same double: how a number is
/// given to set_scene_value (scene_values, live changes) without loss.
std::string exact_text(double v);

/// All keys, in documentation order.
const std::vector<SceneKeyInfo>& scene_keys();

/// Sets one key from its text form. Throws SceneError on an unknown key (with
/// the nearest known key as a suggestion), an unparsable or non-finite number,
/// or a value outside the accepted range.
void set_scene_value(Scene& scene, const std::string& key, const std::string& value);

/// Every key's value in a scene, as text that set_scene_value reads back to
/// the same value (doubles exactly): scene_from_values(scene_values(s)) == s.
/// Two scenes are the same scene when these maps are equal.
std::map<std::string, std::string> scene_values(const Scene& scene);

/// Why a live key has no effect on this scene (a rigid stator's stiffness,
/// k_c without the penalty method, a drive gain without the motor), or ""
/// when it has: such a change is refused, and not offered for live change.
std::string live_key_inert_reason(const std::string& key, const Scene& scene);

/// Checks that hold between keys (e.g. rosenbrock4 is for the penalty method).
void validate_scene(const Scene& scene);

/// Applies a flat key->value map onto the defaults and validates the result.
/// A flexible rotor's file is read once into RotorSettings::loaded, or
/// `loaded` taken when it was read for the same settings.
Scene scene_from_values(const std::map<std::string, std::string>& values,
                        std::shared_ptr<const LoadedFlexibleRotor> loaded = nullptr);

/// The nearest key by edit distance ("" when nothing is close).
std::string nearest_scene_key(const std::string& key);
/// The same over any list of names (the node's own keys, say).
std::string nearest_key(const std::string& key, const std::vector<std::string>& candidates);

}  // namespace rotor_rub::core
