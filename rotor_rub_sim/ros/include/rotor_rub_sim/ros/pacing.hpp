// The node's pace (ROS-free, times passed in: wall seconds, simulated
// seconds): when a simulated time is due at a real-time factor, and the
// factor achieved over the running stretches, the time between them (a
// pause, a step, a lockstep wait for the controller) excluded. Held by
// test_pacing.cpp.
#pragma once

namespace rotor_rub::ros_node {

class Pacing {
 public:
  // Forgets every stretch (a reset).
  void clear() { wall_s_ = sim_s_ = 0.0; }
  // Starts a stretch here: the time since the last anchor does not count.
  void anchor(double wall_s, double sim_s) {
    anchor_wall_s_ = wall_s;
    anchor_sim_s_ = sim_s;
  }
  // Counts the stretch since the anchor, and anchors here.
  void close_stretch(double wall_s, double sim_s) {
    wall_s_ += wall_s - anchor_wall_s_;
    sim_s_ += sim_s - anchor_sim_s_;
    anchor(wall_s, sim_s);
  }
  // The wall time at which sim_s is due at real_time_factor (> 0).
  double due_wall_s(double sim_s, double real_time_factor) const {
    return anchor_wall_s_ + (sim_s - anchor_sim_s_) / real_time_factor;
  }
  // The wall time run so far; running: the open stretch up to now counts too.
  double running_wall_s(double wall_now_s, bool running) const {
    return wall_s_ + (running ? wall_now_s - anchor_wall_s_ : 0.0);
  }
  // Simulated over running wall time (0 before any has run).
  double achieved_real_time_factor(double wall_now_s, double sim_now_s, bool running) const {
    const double sim = sim_s_ + (running ? sim_now_s - anchor_sim_s_ : 0.0);
    const double wall = running_wall_s(wall_now_s, running);
    return wall > 0.0 ? sim / wall : 0.0;
  }

 private:
  double wall_s_ = 0.0, sim_s_ = 0.0;  // the closed stretches
  double anchor_wall_s_ = 0.0, anchor_sim_s_ = 0.0;
};

}  // namespace rotor_rub::ros_node
