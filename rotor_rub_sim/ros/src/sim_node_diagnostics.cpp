// SimNode's diagnostics: the updater's tasks (solver, pace, contact, the
// topics' rates); recording them is RecordedDiagnostics'.
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "rotor_rub_msgs/ParameterChangeFeedback.h"
#include "rotor_rub_msgs/SpeedCommandFeedback.h"
#include "rotor_rub_sim/core/solver_registry.hpp"
#include "rotor_rub_sim/ros/conversions.hpp"
#include "sim_node_io.hpp"
#include "tf2_msgs/TFMessage.h"

namespace rotor_rub::ros_node {

void SimNode::diagnose_solver(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  using diagnostic_msgs::DiagnosticStatus;
  if (const auto& f = sim_->failure()) {
    stat.summaryf(DiagnosticStatus::ERROR, "method failed (%s) at t = %.9g s: %s", core::to_string(f->failure_class),
                  f->time_s, f->message.c_str());
  } else {
    const char* state = status_ == Status::kRunning ? "running" : status_ == Status::kPaused ? "paused" : "finished";
    stat.summaryf(DiagnosticStatus::OK, "%s at t = %.6f s", state, sim_->time());
  }
  const auto& st = sim_->stats();
  stat.add("method", core::to_string(scene_.solver.method));
  stat.add("integrator", core::to_string(core::effective_integrator(scene_)));
  stat.add("simulated time [s]", sim_->time());
  stat.add("steps", st.steps);
  stat.add("rejected steps", st.rejected_steps);
  stat.add("rhs evaluations", st.rhs_evals);
  stat.add("root iterations", st.root_iterations);
  stat.add("restarts", st.restarts);
}

void SimNode::diagnose_pace(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  using diagnostic_msgs::DiagnosticStatus;
  const double achieved = achieved_real_time_factor();
  const double wanted = config_.real_time_factor;
  // Below 90 % of a requested pace the node lags the wall clock.
  if (status_ == Status::kRunning && wanted > 0.0 && running_wall_time_s() > 1.0 && achieved < 0.9 * wanted) {
    stat.summaryf(DiagnosticStatus::WARN, "lagging: real-time factor %.2f of %.2f requested", achieved, wanted);
  } else {
    stat.summaryf(DiagnosticStatus::OK, "real-time factor %.2f (requested %s)", achieved,
                  wanted > 0.0 ? std::to_string(wanted).c_str() : "as fast as possible");
  }
  stat.add("achieved real-time factor", achieved);
  stat.add("requested real-time factor", wanted);
  stat.add("states published", states_published_);
}

void SimNode::diagnose_rate(diagnostic_updater::FrequencyStatus& rate, bool per_revolution,
                            diagnostic_updater::DiagnosticStatusWrapper& stat) {
  using diagnostic_msgs::DiagnosticStatus;
  // diagnostic_updater's frequency status is an ERROR with no message in its
  // window: right for a topic that should flow, wrong for a paused node or a
  // keyphasor below one mark a second.
  const double pace = ros::Time::isSimTime() || !(config_.real_time_factor > 0.0) ? 1.0 : config_.real_time_factor;
  if (status_ != Status::kRunning) {
    stat.summary(DiagnosticStatus::OK, "not running: no publications expected");
  } else if (per_revolution && last_sample_.drive.speed_rad_per_s * pace < 2.0 * M_PI) {
    stat.summary(DiagnosticStatus::OK, "under one revolution a second: not judged");
  } else {
    rate.run(stat);
  }
}

void SimNode::diagnose_contact(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  using diagnostic_msgs::DiagnosticStatus;
  stat.summary(DiagnosticStatus::OK, last_sample_.in_contact ? "in contact (rub)" : "free flight");
  stat.add("in contact", last_sample_.in_contact);
  stat.add("normal force [N]", last_sample_.normal_force_N);
  stat.add("gap [m]", -last_sample_.penetration_m);
  const auto& st = sim_->stats();
  stat.add("touchdowns", st.touchdowns);
  stat.add("liftoffs", st.liftoffs);
  stat.add("grazes", st.grazes);
}

}  // namespace rotor_rub::ros_node
