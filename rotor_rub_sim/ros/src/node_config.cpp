#include "rotor_rub_sim/ros/node_config.hpp"

#include <cmath>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "rotor_rub_sim/core/scene_keys.hpp"

namespace rotor_rub::ros_node {
namespace {

using core::SceneError;

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(15);
  os << v;
  return os.str();
}

double parse_real(const std::string& key, const std::string& text, const std::string& accepted) {
  std::size_t used = 0;
  double v = 0.0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(v)) {
    throw SceneError("node parameter '" + key + "': value '" + text +
                     "' is not a finite number; accepted: " + accepted);
  }
  return v;
}

struct Entry {
  NodeKeyInfo info;
  std::function<void(NodeConfig&, const std::string&)> set;
};

Entry real(std::string key, double lo, bool lo_open, double hi, std::string description,
           std::function<double&(NodeConfig&)> ref) {
  const std::string accepted = std::string(lo_open ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + "]";
  NodeConfig defaults;
  Entry e{{key, accepted, std::move(description), fmt(ref(defaults))}, nullptr};
  e.set = [key, lo, lo_open, hi, accepted, ref](NodeConfig& c, const std::string& text) {
    const double v = parse_real(key, text, accepted);
    if ((lo_open ? !(v > lo) : !(v >= lo)) || v > hi) {
      throw SceneError("node parameter '" + key + "': value " + text + " is out of range; accepted: " + accepted);
    }
    ref(c) = v;
  };
  return e;
}

Entry integer(std::string key, int lo, int hi, std::string description, std::function<int&(NodeConfig&)> ref) {
  const std::string accepted = "integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  NodeConfig defaults;
  Entry e{{key, accepted, std::move(description), std::to_string(ref(defaults))}, nullptr};
  e.set = [key, lo, hi, accepted, ref](NodeConfig& c, const std::string& text) {
    const double v = parse_real(key, text, accepted);
    if (v != std::floor(v) || v < lo || v > hi) {
      throw SceneError("node parameter '" + key + "': value " + text + " is out of range; accepted: " + accepted);
    }
    ref(c) = static_cast<int>(v);
  };
  return e;
}

Entry boolean(std::string key, std::string description, std::function<bool&(NodeConfig&)> ref) {
  NodeConfig defaults;
  Entry e{{key, "true | false", std::move(description), ref(defaults) ? "true" : "false"}, nullptr};
  e.set = [key, ref](NodeConfig& c, const std::string& text) {
    if (text == "true" || text == "True" || text == "1") {
      ref(c) = true;
    } else if (text == "false" || text == "False" || text == "0") {
      ref(c) = false;
    } else {
      throw SceneError("node parameter '" + key + "': value '" + text + "' is not a boolean; accepted: true | false");
    }
  };
  return e;
}

const std::vector<Entry>& entries() {
  static const std::vector<Entry> table = [] {
    std::vector<Entry> t;
    t.push_back(real("real_time_factor", 0, false, 1e9,
                     "pace: simulated seconds per wall second (1 = wall clock; 0 = as fast as possible)",
                     [](NodeConfig& c) -> double& { return c.real_time_factor; }));
    {
      std::string names;
      for (EndAction a : kAllEndActions) names += std::string(names.empty() ? "" : " | ") + to_string(a);
      Entry e{{"end_action", names, "at end_time_s: exit, continue at the last speed, or pause", "exit"}, nullptr};
      e.set = [names](NodeConfig& c, const std::string& text) {
        for (EndAction a : kAllEndActions) {
          if (text == to_string(a)) {
            c.end_action = a;
            return;
          }
        }
        throw SceneError("node parameter 'end_action': value '" + text + "' is not accepted; accepted: " + names);
      };
      t.push_back(e);
    }
    t.push_back(boolean("start_paused", "start paused; resume or step starts the simulation",
                        [](NodeConfig& c) -> bool& { return c.start_paused; }));
    t.push_back(real("stats_rate_hz", 0, true, 1e4, "SolverStats rate in simulated time [Hz]",
                     [](NodeConfig& c) -> double& { return c.stats_rate_hz; }));
    t.push_back(real("diagnostics_rate_hz", 0, true, 1e3, "/diagnostics rate in simulated time [Hz]",
                     [](NodeConfig& c) -> double& { return c.diagnostics_rate_hz; }));
    t.push_back(real("clock_rate_hz", 0, true, 1e7, "/clock rate in simulated time [Hz], at most one per state sample",
                     [](NodeConfig& c) -> double& { return c.clock_rate_hz; }));
    t.push_back(boolean("publish_clock", "publish /clock (one node per graph should)",
                        [](NodeConfig& c) -> bool& { return c.publish_clock; }));
    t.push_back(real("marker_rate_hz", 0, false, 1e4, "RViz marker rate in simulated time [Hz]; 0 = no markers",
                     [](NodeConfig& c) -> double& { return c.marker_rate_hz; }));
    t.push_back(real("tf_rate_hz", 0, false, 1e4,
                     "tf rate in simulated time [Hz]: frames <ns>/stator and <ns>/rotor (spinning with phi) in "
                     "frame_id; 0 = none",
                     [](NodeConfig& c) -> double& { return c.tf_rate_hz; }));
    t.push_back(real("shaft_rate_hz", 0, false, 1e4,
                     "a flexible rotor's deflected shaft (topic shaft and its markers) in simulated time [Hz]; 0 = "
                     "none; nothing without a rotor_file",
                     [](NodeConfig& c) -> double& { return c.shaft_rate_hz; }));
    t.push_back(real("marker_scale", 0, true, 1e6, "marker length per model length (1000: 1 mm is drawn as 1 m)",
                     [](NodeConfig& c) -> double& { return c.marker_scale; }));
    t.push_back(real("marker_force_scale_m_per_N", 0, true, 1e3,
                     "contact force arrow length in RViz per newton [m/N] (marker_scale not applied)",
                     [](NodeConfig& c) -> double& { return c.marker_force_scale_m_per_N; }));
    t.push_back(integer("orbit_trail_samples", 2, 1000000, "state samples kept in the orbit trail marker",
                        [](NodeConfig& c) -> int& { return c.orbit_trail_samples; }));
    {
      Entry e{{"frame_id", "non-empty frame name", "frame of every header (the stator's rest frame)", "world"},
              nullptr};
      e.set = [](NodeConfig& c, const std::string& text) {
        if (text.empty()) {
          throw SceneError("node parameter 'frame_id': value '' is not accepted; accepted: a non-empty frame name");
        }
        c.frame_id = text;
      };
      t.push_back(e);
    }
    {
      Entry e{{"record_bag", "a writable file path, or empty for none",
               "record every topic of the node into this bag, in-process (lossless at any pace)", ""},
              nullptr};
      e.set = [](NodeConfig& c, const std::string& text) { c.record_bag = text; };
      t.push_back(e);
    }
    t.push_back(real("record_flush_period_s", 0, true, 3600,
                     "wall time between writes of the recording to the file; bounds the loss on SIGKILL [s]",
                     [](NodeConfig& c) -> double& { return c.record_flush_period_s; }));
    t.push_back(real("lockstep_period_s", 0, false, 1,
                     "closed-loop lockstep: simulated time between waits for the controller's command; 0 = off [s]",
                     [](NodeConfig& c) -> double& { return c.lockstep_period_s; }));
    t.push_back(real("lockstep_timeout_s", 0, true, 3600,
                     "wall time the node waits for the controller's command in lockstep before going on [s]",
                     [](NodeConfig& c) -> double& { return c.lockstep_timeout_s; }));
    t.push_back(integer("wait_for_subscribers", 0, 1000,
                        "before simulating, wait for this many subscribers on every data topic",
                        [](NodeConfig& c) -> int& { return c.wait_for_subscribers; }));
    t.push_back(integer("wait_for_state_subscribers", 0, 1000,
                        "before simulating, wait for this many subscribers on state (and, in lockstep, one on "
                        "lockstep_state)",
                        [](NodeConfig& c) -> int& { return c.wait_for_state_subscribers; }));
    t.push_back(real("wait_timeout_s", 0, true, 1e6, "wall time to wait for subscribers before failing [s]",
                     [](NodeConfig& c) -> double& { return c.wait_timeout_s; }));
    t.push_back(integer("publish_queue_size", 0, 100000000,
                        "outgoing queue per subscriber; 0 = unbounded (never drops a message)",
                        [](NodeConfig& c) -> int& { return c.publish_queue_size; }));
    t.push_back(real("exit_linger_s", 0, false, 600, "wall time to let subscribers drain before exiting [s]",
                     [](NodeConfig& c) -> double& { return c.exit_linger_s; }));
    return t;
  }();
  return table;
}

std::vector<std::string> all_key_names() {
  std::vector<std::string> names;
  for (const auto& e : entries()) names.push_back(e.info.key);
  for (const auto& k : core::scene_keys()) names.push_back(k.key);
  return names;
}

}  // namespace

// No default label: -Werror=switch names an action added without a name.
const char* to_string(EndAction a) {
  switch (a) {
    case EndAction::kExit:
      return "exit";
    case EndAction::kContinue:
      return "continue";
    case EndAction::kPause:
      return "pause";
  }
  throw std::logic_error("to_string: not an EndAction");
}

const std::vector<NodeKeyInfo>& node_keys() {
  static const std::vector<NodeKeyInfo> infos = [] {
    std::vector<NodeKeyInfo> v;
    for (const auto& e : entries()) v.push_back(e.info);
    return v;
  }();
  return infos;
}

bool is_node_key(const std::string& key) {
  for (const auto& e : entries()) {
    if (e.info.key == key) return true;
  }
  return false;
}

void set_node_value(NodeConfig& config, const std::string& key, const std::string& value) {
  for (const auto& e : entries()) {
    if (e.info.key == key) {
      e.set(config, value);
      return;
    }
  }
  const std::string near = core::nearest_key(key, all_key_names());
  throw SceneError("unknown parameter '" + key + "'" + (near.empty() ? "" : "; did you mean '" + near + "'?") +
                       " (config/scene_template.yaml lists the scene keys, docs/node.md the node keys)",
                   key, SceneError::Kind::kUnknownKey);
}

NodeSetup node_setup_from_values(const std::map<std::string, std::string>& values) {
  std::map<std::string, std::string> scene_values;
  NodeSetup setup;
  for (const auto& [key, value] : values) {
    if (is_node_key(key)) {
      set_node_value(setup.config, key, value);
      continue;
    }
    bool scene_key = false;
    for (const auto& k : core::scene_keys()) scene_key = scene_key || k.key == key;
    if (!scene_key) set_node_value(setup.config, key, value);  // throws, suggesting the nearest of both tables
    scene_values[key] = value;
  }
  setup.scene = core::scene_from_values(scene_values);
  // The lockstep state is a sample: its period must be a whole number of
  // output periods (at most 1e-9 relative off).
  const double periods = setup.config.lockstep_period_s * setup.scene.output_rate_hz;
  if (setup.config.lockstep_period_s > 0.0 &&
      (periods < 1.0 - 1e-9 || std::abs(periods - std::round(periods)) > 1e-9 * periods)) {
    std::ostringstream os;
    os << "node parameter 'lockstep_period_s': value " << setup.config.lockstep_period_s
       << " is not accepted; accepted: 0 or a whole multiple of the output period 1/output_rate_hz = "
       << 1.0 / setup.scene.output_rate_hz << " s";
    throw core::SceneError(os.str());
  }
  return setup;
}

}  // namespace rotor_rub::ros_node
