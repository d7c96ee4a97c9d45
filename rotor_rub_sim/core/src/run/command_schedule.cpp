#include "rotor_rub_sim/core/command_schedule.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "rotor_rub_sim/core/scene_keys.hpp"

namespace rotor_rub::core {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string at_time(double t_s) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", t_s);
  return buf;
}

// The scene's values of these keys now (NaN: not a scene key).
std::map<std::string, double> values_now(const Scene& scene, const std::map<std::string, std::string>& changes) {
  const std::map<std::string, std::string> values = scene_values(scene);
  std::map<std::string, double> out;
  for (const auto& change : changes) {
    const auto v = values.find(change.first);
    out[change.first] = v == values.end() ? kNaN : std::stod(v->second);
  }
  return out;
}

const char* const kFailed = "the simulation has failed; call the reset service first";

}  // namespace

std::string CommandSchedule::past_stamp(double stamp_s, double now_s) {
  if (!(stamp_s > 0.0) || stamp_s >= now_s) return "";
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "stamp %.9f s is in the past (simulated time %.9f s); accepted: 0 (the next instant reached) or a "
                "time not yet simulated",
                stamp_s, now_s);
  return buf;
}

void CommandSchedule::enqueue(Pending p) {
  const auto at = std::upper_bound(pending_.begin(), pending_.end(), p.time_s,
                                   [](double t, const Pending& q) { return t < q.time_s; });
  pending_.insert(at, std::move(p));
}

void CommandSchedule::clear() {
  pending_.clear();
  ramps_.clear();
  applied_target_ = applied_accel_ = kNaN;
}

SpeedAnswer CommandSchedule::command_speed(Simulation& sim, double stamp_s, double target_rad_per_s,
                                           double accel_rad_per_s2) {
  SpeedAnswer a;
  const double scene_accel = sim.scene().speed.acceleration_rad_per_s2;
  a.accel_rad_per_s2 = accel_rad_per_s2 == 0.0 ? scene_accel : accel_rad_per_s2;
  try {
    if (sim.failure()) throw std::invalid_argument(kFailed);
    if (!(accel_rad_per_s2 >= 0.0) || std::isinf(accel_rad_per_s2)) {
      std::ostringstream os;
      os << "speed command acceleration_limit ";
      if (std::isnan(accel_rad_per_s2)) {
        os << "NaN";  // a NaN's sign bit is noise
      } else {
        os << accel_rad_per_s2;
      }
      os << " rad/s^2 " << (std::isfinite(accel_rad_per_s2) ? "is out of range" : "is not a finite number")
         << "; accepted: (0, inf), or 0 for the scene's acceleration_rad_per_s2 = " << scene_accel;
      throw std::invalid_argument(os.str());
    }
    if (a.accel_rad_per_s2 == 0.0) {  // a constant-speed scene's 0 would never reach the target
      throw std::invalid_argument(
          "speed command acceleration_limit 0 takes the scene's acceleration_rad_per_s2, which is 0 (a "
          "constant-speed scene); accepted: (0, inf)");
    }
    check_speed_command(sim.scene(), target_rad_per_s, a.accel_rad_per_s2);
  } catch (const std::invalid_argument& e) {
    a.reason = e.what();
    a.effective_time_s = sim.time();
    return a;
  }
  a.accepted = true;
  const double in_force_target =
      std::isnan(applied_target_) ? sim.scene().speed.target_speed_rad_per_s : applied_target_;
  const double in_force_accel = std::isnan(applied_accel_) ? scene_accel : applied_accel_;
  if (stamp_s <= sim.time() && pending_.empty() && target_rad_per_s == in_force_target &&
      a.accel_rad_per_s2 == in_force_accel) {
    a.effective_time_s = sim.time();  // a repeat of the command in force: nothing changes
  } else if (stamp_s > sim.time()) {
    Pending p;
    p.time_s = stamp_s;
    p.target_rad_per_s = target_rad_per_s;
    p.accel_rad_per_s2 = a.accel_rad_per_s2;
    enqueue(std::move(p));
    a.effective_time_s = stamp_s;
  } else {
    sim.command_speed(target_rad_per_s, a.accel_rad_per_s2);
    applied_target_ = target_rad_per_s;
    applied_accel_ = a.accel_rad_per_s2;
    a.effective_time_s = sim.time();
  }
  return a;
}

void CommandSchedule::change_parameters(Simulation& sim, double stamp_s,
                                        const std::map<std::string, std::string>& changes, std::uint32_t id,
                                        const std::string& source, std::vector<ChangeAnswer>& answers) {
  std::string refused = changes.empty() ? "no keys" : past_stamp(stamp_s, sim.time());
  // Checked on receipt against the scene in force (nothing is queued that
  // is bound to fail); again at the stamp, where the rules between keys and
  // the state decide the rest (a clearance closed onto the rotor).
  if (refused.empty()) {
    try {
      if (sim.failure()) throw SceneError(kFailed);
      with_live_changes(sim.scene(), changes, false);
    } catch (const SceneError& e) {
      refused = e.what();
    }
  }
  Pending p;
  p.time_s = std::max(stamp_s, sim.time());
  p.kind = Pending::Kind::kParameters;
  p.changes = changes;
  p.id = id;
  p.source = source;
  if (!refused.empty()) {
    ChangeAnswer a;
    a.id = id;
    a.source = source;
    a.changes = changes;
    a.start_s = a.end_s = sim.time();
    a.reason = refused;
    for (const auto& c : changes) a.from[c.first] = kNaN;
    answers.push_back(std::move(a));
  } else if (stamp_s > sim.time()) {
    enqueue(std::move(p));
  } else {
    apply_change(sim, p, answers);
  }
}

double CommandSchedule::inject_fault(Simulation& sim, double stamp_s, const Fault& fault, std::uint32_t id,
                                     std::vector<ChangeAnswer>& answers) {
  check_fault(fault, output_rate_hz_);
  if (fault.kind == FaultKind::kSupportLoosening && sim.scene().model.stator_model == StatorModel::kRigid) {
    throw std::invalid_argument("fault support_loosening has no effect on a rigid stator (stator_model rigid)");
  }
  if (sim.failure()) throw std::invalid_argument(kFailed);
  const std::string past = past_stamp(stamp_s, sim.time());
  if (!past.empty()) throw std::invalid_argument(past);
  // Checked on receipt as a parameter change is, on the scene in force now:
  // a fault the scene cannot take (a blade loss at a node without a disk)
  // is refused to the caller, not accepted and then refused at its stamp. A
  // ramp's first and last steps bound the rest.
  const std::vector<FaultStep> steps = fault_steps(fault, sim.scene(), output_rate_hz_);
  if (!steps.empty()) {
    with_live_changes(sim.scene(), steps.front().changes, false);
    with_live_changes(sim.scene(), steps.back().changes, false);
  }
  Pending p;
  p.kind = Pending::Kind::kFault;
  p.time_s = std::max(stamp_s, sim.time());
  p.fault = fault;
  p.id = id;
  p.source = fault_source(fault.kind);
  const double first_s = p.time_s + (steps.empty() ? 0.0 : steps.front().offset_s);
  enqueue(std::move(p));
  apply_due(sim, answers);  // one due now applies at once, as an unstamped change
  return first_s;
}

void CommandSchedule::apply_due(Simulation& sim, std::vector<ChangeAnswer>& answers) {
  while (!pending_.empty() && pending_.front().time_s <= sim.time()) {
    const Pending p = pending_.front();
    pending_.pop_front();
    switch (p.kind) {
      case Pending::Kind::kSpeed:
        sim.command_speed(p.target_rad_per_s, p.accel_rad_per_s2);  // checked on receipt
        applied_target_ = p.target_rad_per_s;
        applied_accel_ = p.accel_rad_per_s2;
        break;
      case Pending::Kind::kParameters:
        if (p.ramp != 0) {
          apply_ramp_step(sim, p, answers);
        } else {
          apply_change(sim, p, answers);
        }
        break;
      case Pending::Kind::kFault:
        expand_fault(sim, p, answers);
        break;
    }
  }
}

CommandSchedule::Outcome CommandSchedule::try_change(Simulation& sim, std::map<std::string, std::string> changes,
                                                     bool stop_at_rotor,
                                                     const std::vector<RotorUnbalance>& unbalances_added) const {
  // An unbalance added (a flexible rotor's blade loss) is echoed as the
  // change it made: its node, m e and angle on the shaft from the
  // keyphasor's notch (the file's angle turned by unbalance_phase_rad).
  Outcome o;
  o.echoed = changes;
  for (const RotorUnbalance& u : unbalances_added) {
    o.echoed["added_unbalance_node"] = std::to_string(u.node);
    o.echoed["added_unbalance_me_kg_m"] = exact_text(u.me_kg_m);
    o.echoed["added_unbalance_phase_rad"] =
        exact_text(std::remainder(u.phase_rad + sim.scene().model.unbalance_phase_rad, 2.0 * M_PI));
  }
  try {
    if (sim.failure()) throw SceneError(kFailed);
    const auto closure = changes.find("clearance_m");
    if (stop_at_rotor && closure != changes.end()) {
      // Down to the rotor, never up: a rotor pressed into the bore (the
      // penalty method's overlap) leaves the clearance where it is.
      const double floor_m = std::min(sim.rotor_stator_distance_m(), sim.scene().model.clearance_m);
      if (std::stod(closure->second) < floor_m) {
        closure->second = exact_text(floor_m);
        o.echoed["clearance_m"] = closure->second;
        o.reason = "the closure stopped at the rotor at t = " + at_time(sim.time()) + " s (clearance held at " +
                   closure->second + " m)";
      }
    }
    sim.change_parameters(changes, unbalances_added);
  } catch (const std::exception& e) {  // SceneError: refused
    o.reason = e.what();
    return o;
  }
  if (sim.failure()) {
    o.reason = "the method failed restarting under the change: " + sim.failure()->message;
    return o;
  }
  o.accepted = true;
  return o;
}

void CommandSchedule::apply_change(Simulation& sim, const Pending& p, std::vector<ChangeAnswer>& answers) {
  ChangeAnswer a;
  a.id = p.id;
  a.source = p.source;
  a.start_s = sim.time();
  a.from = values_now(sim.scene(), p.changes);
  const Outcome o = try_change(sim, p.changes, p.stop_at_rotor, p.unbalances_added);
  a.accepted = o.accepted;
  a.changes = o.echoed;
  a.reason = o.reason;
  a.end_s = sim.time();
  a.steps = o.accepted ? 1 : 0;
  if (!o.accepted) {
    for (auto& f : a.from) f.second = kNaN;
  }
  answers.push_back(std::move(a));
}

void CommandSchedule::apply_ramp_step(Simulation& sim, const Pending& p, std::vector<ChangeAnswer>& answers) {
  OpenRamp& r = ramps_[p.ramp];
  if (r.applied == 0) {
    r.id = p.id;
    r.source = p.source;
    r.start_s = sim.time();
    r.from = values_now(sim.scene(), p.changes);
  }
  const Outcome o = try_change(sim, p.changes, p.stop_at_rotor, p.unbalances_added);
  if (o.accepted) {
    ++r.applied;
    r.reached = o.echoed;
    if (r.note.empty() && !o.reason.empty()) r.note = o.reason;
    if (!p.ramp_last) return;
  }
  // One answer for the ramp: its span and where it took the keys; a step
  // refused ends it there (the steps before it stand; the rest are dropped).
  ChangeAnswer a;
  a.id = r.id;
  a.source = r.source;
  a.accepted = r.applied > 0;
  a.changes = a.accepted ? r.reached : o.echoed;
  a.start_s = a.accepted ? r.start_s : sim.time();
  a.end_s = sim.time();
  a.steps = r.applied;
  a.reason = r.note;
  if (a.accepted) {
    a.from = r.from;
  } else {
    for (const auto& c : o.echoed) a.from[c.first] = kNaN;
  }
  if (!o.accepted) {
    a.reason = "the ramp stopped at t = " + at_time(sim.time()) + " s after " + std::to_string(r.applied) +
               " steps: " + o.reason;
    const std::uint64_t ramp = p.ramp;
    pending_.erase(
        std::remove_if(pending_.begin(), pending_.end(), [ramp](const Pending& q) { return q.ramp == ramp; }),
        pending_.end());
  }
  ramps_.erase(p.ramp);
  answers.push_back(std::move(a));
}

void CommandSchedule::close_open_ramps(const Simulation& sim, const std::string& why,
                                       std::vector<ChangeAnswer>& answers) {
  for (const auto& [serial, r] : ramps_) {
    ChangeAnswer a;
    a.id = r.id;
    a.source = r.source;
    a.accepted = r.applied > 0;  // cut before its first step: nothing changed
    a.changes = r.reached;
    a.from = r.from;
    a.start_s = r.applied > 0 ? r.start_s : sim.time();
    a.end_s = sim.time();
    a.steps = r.applied;
    const std::string cut =
        "the ramp was cut at t = " + at_time(sim.time()) + " s after " + std::to_string(r.applied) + " steps: " + why;
    a.reason = r.note.empty() ? cut : r.note + "; " + cut;
    answers.push_back(std::move(a));
  }
  ramps_.clear();
  pending_.erase(std::remove_if(pending_.begin(), pending_.end(), [](const Pending& q) { return q.ramp != 0; }),
                 pending_.end());
}

void CommandSchedule::expand_fault(Simulation& sim, const Pending& p, std::vector<ChangeAnswer>& answers) {
  std::vector<FaultStep> steps;
  try {
    steps = fault_steps(p.fault, sim.scene(), output_rate_hz_);
  } catch (const std::invalid_argument& e) {  // checked on receipt; the scene may have changed since
    ChangeAnswer a;
    a.id = p.id;
    a.source = p.source;
    a.start_s = a.end_s = sim.time();
    a.reason = e.what();
    answers.push_back(std::move(a));
    return;
  }
  // A step at the fault's instant applies now, in the fault's place among
  // the commands of that instant (queued, it would land after commands
  // that arrived later and overwrite them: FaultsTakeTheirPlaceAtTheirStamp);
  // a ramp's steps wait in the queue for their times, its record opened now
  // so that a ramp cut before its first step is answered too.
  const std::uint64_t ramp = steps.size() > 1 ? next_ramp_++ : 0;
  if (ramp != 0) {
    OpenRamp& r = ramps_[ramp];
    r.id = p.id;
    r.source = p.source;
  }
  for (FaultStep& step : steps) {
    Pending q;
    q.time_s = sim.time() + step.offset_s;
    q.kind = Pending::Kind::kParameters;
    q.ramp = ramp;
    q.ramp_last = &step == &steps.back();
    q.changes = std::move(step.changes);
    q.id = p.id;
    q.source = p.source;
    q.stop_at_rotor = step.stop_at_rotor;
    q.unbalances_added = std::move(step.unbalances_added);
    if (ramp == 0 && step.offset_s == 0.0) {
      apply_change(sim, q, answers);
    } else {
      enqueue(std::move(q));
    }
  }
}

}  // namespace rotor_rub::core
