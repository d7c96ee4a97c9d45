// The node's own settings (pacing, publishing, end of run), apart from the
// scene. A plain struct with a key table like the scene's, parsed from text so
// that it is tested without a master; the rosparam loader only gathers text.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::ros_node {

// What the node does when the simulated time reaches the scene's end_time_s.
enum class EndAction {
  kExit,      // publish the final statistics, then shut down (exit status 0)
  kContinue,  // keep running at the last commanded speed
  kPause,     // stay up, paused, for reset or inspection
};
inline constexpr std::array<EndAction, 3> kAllEndActions{EndAction::kExit, EndAction::kContinue, EndAction::kPause};
const char* to_string(EndAction a);

struct NodeConfig {
  // 1 = wall-clock pace, 2 = twice as fast, 0 = as fast as possible.
  double real_time_factor = 1.0;
  EndAction end_action = EndAction::kExit;
  bool start_paused = false;                 // wait for resume or step before simulating
  double stats_rate_hz = 10.0;               // SolverStats, in simulated time
  double diagnostics_rate_hz = 2.0;          // /diagnostics, in simulated time
  double clock_rate_hz = 1000.0;             // /clock, in simulated time (capped by the state rate)
  bool publish_clock = true;                 // one node per ROS graph should publish /clock
  double marker_rate_hz = 30.0;              // RViz markers, in simulated time; 0 = none
  double tf_rate_hz = 50.0;                  // tf frames stator and rotor, in simulated time; 0 = none
  double shaft_rate_hz = 50.0;               // a flexible rotor's deflected shaft, in simulated time; 0 = none
  double marker_scale = 1000.0;              // drawn length per model length (1000: 1 mm shows as 1 m)
  double marker_force_scale_m_per_N = 0.01;  // force arrow length in RViz per newton (not scaled)
  int orbit_trail_samples = 500;             // state samples kept in the orbit trail marker
  std::string frame_id = "world";            // frame of every header (the stator's rest frame)
  // Before simulating, wait until every data topic has at least this many
  // subscribers (a recorder, say), so that nothing is published unheard.
  int wait_for_subscribers = 0;
  // The same for state alone (monitoring and control nodes), and, with
  // lockstep, one subscriber on lockstep_state (the controller).
  int wait_for_state_subscribers = 0;
  double wait_timeout_s = 30.0;  // wall time; the node exits with an error when it runs out
  // Outgoing queue per subscriber for state, events, stats, feedback. 0 =
  // unbounded: the node never drops a message; a slow subscriber costs memory.
  int publish_queue_size = 0;
  double exit_linger_s = 1.0;  // wall time to let subscribers drain before exiting
  // Records every message the node publishes (and the speed commands it
  // receives) into this bag, in-process: nothing is lost at any pace. "" = off.
  std::string record_bag;
  // Wall time between hand-overs of the recorded data to the kernel: a node
  // killed with SIGKILL loses at most this much recording (SIGINT loses none).
  double record_flush_period_s = 1.0;
  // Lockstep (closed loop, reproducible at any pace): every lockstep_period_s
  // of simulated time the node publishes lockstep_state and waits until a
  // speed command stamped at that time (or later) arrives, at most
  // lockstep_timeout_s of wall time. 0 = off.
  double lockstep_period_s = 0.0;
  double lockstep_timeout_s = 10.0;
};

struct NodeKeyInfo {
  std::string key;
  std::string accepted;
  std::string description;
  std::string default_value;
};
const std::vector<NodeKeyInfo>& node_keys();

// Sets one node key from text; throws core::SceneError naming the key, the
// value and the accepted range (unknown keys: nearest known key suggested).
void set_node_value(NodeConfig& config, const std::string& key, const std::string& value);
bool is_node_key(const std::string& key);

// Splits flat private parameters into scene and node settings, validates
// both, and throws core::SceneError for any bad or unknown key.
struct NodeSetup {
  core::Scene scene;
  NodeConfig config;
};
NodeSetup node_setup_from_values(const std::map<std::string, std::string>& values);

}  // namespace rotor_rub::ros_node
