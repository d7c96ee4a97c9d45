#include "rotor_rub_sim/core/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "methods/event_location.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/scene_keys.hpp"
#include "rotor_rub_sim/core/solver_registry.hpp"
#include "run/cost_profiler.hpp"

namespace rotor_rub::core {

std::unique_ptr<ContactMethod> make_contact_method(const Scene& scene) {
  const SolverEntry* entry = find_solver(scene.solver.method, effective_integrator(scene));
  if (entry == nullptr) {
    validate_scene(scene);  // throws SceneError naming the key and the accepted values
    throw std::logic_error("make_contact_method: the registry offers no such method and integrator");
  }
  return entry->make[static_cast<std::size_t>(rotor_kind(scene))](scene);
}

namespace {

// The scene checked as a scene file's would be (every key's range through
// the key table, then the rules between keys), with `auto` resolved, so
// scene() tells which integrator runs.
Scene checked_scene(Scene scene) {
  // Every key's value read back through the key table (exact: scene_values'
  // texts), which throws SceneError naming a key out of its range, then
  // validate_scene; the scene itself is kept (it may hold what no key sets,
  // profile_cost).
  scene.rotor.loaded = scene_from_values(scene_values(scene), scene.rotor.loaded).rotor.loaded;
  scene.solver.integrator = effective_integrator(scene);
  return scene;
}

}  // namespace

Simulation::Simulation(const Scene& scene)
    : scene_(checked_scene(scene)),
      profile_(scene_.speed),
      method_(make_contact_method(scene_)),
      limits_(InvariantLimits::for_scene(scene_, contact_radius_of(scene_))),
      wall_budget_s_(scene_.solver.max_wall_time_s) {
  // Room for a step's events (a touchdown and its lift-off, a few grazes),
  // so that the first contact allocates nothing (test_allocations).
  step_events_.reserve(16);
  // Start at rest, centred: the run-up's initial condition.
  method_->start(0.0, StationModel(scene_.model).initial_kinematics(profile_.at(0.0)), profile_.segment_at(0.0));
  const double two_pi = 2.0 * M_PI;
  next_mark_angle_rad_ = two_pi * (std::floor(scene_.speed.initial_angle_rad / two_pi) + 1.0);
}

void check_speed_command(const Scene& scene, double target_rad_per_s, double accel_magnitude_rad_per_s2) {
  const double vmax = scene.speed.max_speed_rad_per_s;
  auto verdict = [](double v) { return std::isfinite(v) ? "is out of range" : "is not a finite number"; };
  // A NaN's sign bit is noise ("-nan" from a YAML .nan): name it plainly.
  auto shown = [](double v) {
    std::ostringstream os;
    if (std::isnan(v)) {
      os << "NaN";
    } else {
      os << v;
    }
    return os.str();
  };
  if (!std::isfinite(target_rad_per_s) || target_rad_per_s < 0.0 || target_rad_per_s > vmax) {
    std::ostringstream os;
    os << "speed command target " << shown(target_rad_per_s) << " rad/s " << verdict(target_rad_per_s)
       << "; accepted: [0, " << vmax << "] (max_speed_rad_per_s)";
    throw std::invalid_argument(os.str());
  }
  if (!std::isfinite(accel_magnitude_rad_per_s2) || accel_magnitude_rad_per_s2 <= 0.0) {
    std::ostringstream os;
    os << "speed command acceleration " << shown(accel_magnitude_rad_per_s2) << " rad/s^2 "
       << verdict(accel_magnitude_rad_per_s2) << "; accepted: (0, inf)";
    throw std::invalid_argument(os.str());
  }
}

void Simulation::command_speed(double target_rad_per_s, double accel_magnitude_rad_per_s2) {
  check_speed_command(scene_, target_rad_per_s, accel_magnitude_rad_per_s2);
  // The method's current step may extend past time_s_: restart it there.
  profile_.command(time_s_, target_rad_per_s, accel_magnitude_rad_per_s2);
  method_->change_segment(time_s_, profile_.segment_at(time_s_));
  break_due_ = false;
  // Events found beyond time_s_ belonged to the old profile.
  std::vector<ContactEvent> kept;
  for (const auto& e : step_events_) {
    if (e.t_s <= time_s_) kept.push_back(e);
  }
  step_events_.swap(kept);
}

namespace {

std::string shown(double v) {
  std::ostringstream os;
  os.precision(12);
  os << v;
  return os.str();
}

}  // namespace

Scene with_live_changes(const Scene& running, const std::map<std::string, std::string>& changes,
                        bool rules_between_keys) {
  Scene next = running;
  for (const auto& change : changes) {
    const std::string& key = change.first;  // named, not a structured binding: a lambda captures it (C++17)
    const std::string& value = change.second;
    const auto& keys = scene_keys();
    const auto info = std::find_if(keys.begin(), keys.end(), [&](const SceneKeyInfo& i) { return i.key == key; });
    if (info == keys.end()) {
      set_scene_value(next, key, value);  // an unknown key: throws SceneError naming the nearest one
      throw std::logic_error("with_live_changes: the key table and set_scene_value disagree on '" + key + "'");
    }
    if (!info->live) {
      throw SceneError("scene key '" + key + "' cannot change while running: " + info->live_refusal);
    }
    const std::string inert = live_key_inert_reason(key, running);
    if (!inert.empty()) throw SceneError("scene key '" + key + "' is not changed: " + inert);
    set_scene_value(next, key, value);  // throws: out of range
  }
  if (!rules_between_keys) return next;
  // The rules between keys, on the scene as a file would give it: a run
  // moved past its end (a node's end_action continue: end_time_s infinity)
  // is checked with the largest end a file may give.
  Scene probe = next;
  probe.end_time_s = std::min(probe.end_time_s, 1e6);
  static_cast<void>(checked_scene(probe));
  return next;
}

Scene with_unbalances_added(const Scene& running, const std::vector<RotorUnbalance>& added) {
  if (added.empty()) return running;
  if (rotor_kind(running) == RotorKind::kJeffcott) {
    throw SceneError(
        "an unbalance added at a node needs a flexible rotor (rotor_file); the Jeffcott rotor's unbalance is the "
        "scene keys eccentricity_m and unbalance_phase_rad");
  }
  Scene next = running;
  load_rotor(next);
  auto loaded = std::make_shared<LoadedFlexibleRotor>(*next.rotor.loaded);
  try {
    loaded->model = std::make_shared<const FlexibleRotorModel>(loaded->model->with_unbalances(added));
  } catch (const std::invalid_argument& e) {
    throw SceneError(std::string("rotor_file '") + running.rotor.file + "': " + e.what());
  }
  next.rotor.loaded = std::move(loaded);
  return next;
}

void Simulation::change_parameters(const std::map<std::string, std::string>& changes,
                                   const std::vector<RotorUnbalance>& unbalances_added) {
  if (failure_) throw SceneError("the simulation has failed (" + failure_->message + "); nothing to change");
  Scene next = with_live_changes(scene_, changes, unbalances_added.empty());
  if (!unbalances_added.empty()) {
    // The rules between keys on the rotor with its new unbalances (the
    // motor's spin bound and RK4's step depend on them).
    next = with_unbalances_added(next, unbalances_added);
    Scene probe = next;
    probe.end_time_s = std::min(probe.end_time_s, 1e6);
    static_cast<void>(checked_scene(probe));
  }
  // The stator must not land inside the rotor: a clearance (or a rigid
  // stator's offset) may close on the rotor down to where it is now, no
  // further (a contact would need an impact with no closing speed to
  // decide). atol: the methods' own penetration tolerance.
  const Sample now = method_->sample(time_s_);
  const bool rigid = next.model.stator_model == StatorModel::kRigid;
  const Vec2 stator = rigid ? Vec2(next.model.stator_offset_x_m, next.model.stator_offset_y_m) : now.kin.stator_pos;
  const double distance_m = (now.kin.rotor_pos - stator).norm();
  const double penetration_m = distance_m - next.model.clearance_m;
  if (penetration_m > std::max(now.penetration_m, 0.0) + scene_.solver.atol) {
    std::string keys;
    for (const auto& [key, value] : changes) keys += (keys.empty() ? "'" : ", '") + key + "' = " + value;
    throw SceneError("scene keys " + keys + " are refused at t = " + shown(time_s_) +
                     " s: the stator would overlap the rotor by " + shown(penetration_m) +
                     " m (rotor-stator distance " + shown(distance_m) + " m, new clearance " +
                     shown(next.model.clearance_m) + " m); accepted now: a clearance of at least the distance");
  }
  scene_.model = next.model;
  if (next.rotor.loaded != scene_.rotor.loaded) {
    scene_.rotor.loaded = next.rotor.loaded;
    method_->change_rotor(time_s_, scene_.rotor.loaded->model);
  }
  limits_ = InvariantLimits::for_scene(scene_, contact_radius_of(scene_));
  // Events found beyond time_s_ were found under the old parameters; the
  // method restarts here (a drive break it had reached stays due).
  std::vector<ContactEvent> kept;
  for (const auto& e : step_events_) {
    if (e.t_s <= time_s_) kept.push_back(e);
  }
  step_events_.swap(kept);
  // The restart may fail as a step may (a force that does not converge at
  // the new state): the run ends there, as advance_to ends it.
  try {
    method_->change_model(time_s_, scene_.model, step_events_);
  } catch (const MethodFailure& f) {
    failure_ = RunFailure{f.failure_class, f.time_s, f.what()};
  }
  break_due_ = break_due_ && time_s_ >= t_limit_s_;
}

double Simulation::rotor_stator_distance_m() const {
  const Sample s = method_->sample(time_s_);
  return s.penetration_m + scene_.model.clearance_m;
}

void Simulation::set_end_time(double t_s) {
  if (!(t_s >= time_s_)) {
    throw std::invalid_argument("end time " + std::to_string(t_s) + " s is before the simulated time " +
                                std::to_string(time_s_) + " s");
  }
  // The wall budget bounds the scene's run; a node that keeps running past
  // the scene's end (end_action continue) runs as long as it is asked to.
  if (t_s > scene_.end_time_s) wall_budget_s_ = std::numeric_limits<double>::infinity();
  scene_.end_time_s = t_s;
}

void Simulation::count_and_deliver(const ContactEvent& e, SimulationObserver& observer) {
  RunStats& st = method_->mutable_stats();
  ++(e.kind == EventKind::kTouchdown ? st.touchdowns : e.kind == EventKind::kLiftoff ? st.liftoffs : st.grazes);
  observer.on_event(e);
}

void Simulation::deliver_marks_before(double t_s, bool inclusive, SimulationObserver& observer) {
  if (!observer.wants_keyphasor()) return;
  // An observer that did not want marks before: start from the next one.
  const double two_pi = 2.0 * M_PI;
  const bool motor = scene_.model.drive_model == DriveModel::kMotor;
  const double angle_now = motor ? method_->sample(time_s_).drive.angle_rad : profile_.at(time_s_).angle_rad;
  if (next_mark_angle_rad_ < angle_now) next_mark_angle_rad_ = two_pi * (std::floor(angle_now / two_pi) + 1.0);
  for (;;) {
    // Marks are not before time_s_ (the angle never decreases).
    const double t_mark =
        motor ? spin_angle_time(next_mark_angle_rad_, t_s) : profile_.time_at_angle(time_s_, next_mark_angle_rad_);
    if (inclusive ? t_mark > t_s : t_mark >= t_s) return;
    const Sample s = method_->sample(t_mark);
    check_invariants(s, limits_);
    observer.on_keyphasor(s);
    next_mark_angle_rad_ += two_pi;
  }
}

double Simulation::spin_angle_time(double angle_rad, double t_s) const {
  // A motor's spin angle is a state: the mark is located on the method's
  // dense output over [time(), t_s] (inside its last step), like a contact
  // event, with TOMS 748 to kEventTimeTolerance_s. Not counted in the run's
  // cost: whether marks are wanted must not change what a run reports.
  constexpr double kNever = std::numeric_limits<double>::infinity();
  auto behind = [this, angle_rad](double t) { return method_->sample(t).drive.angle_rad - angle_rad; };
  const double f0 = behind(time_s_), f1 = behind(t_s);
  if (f1 < 0.0) return kNever;
  if (f0 >= 0.0) return time_s_;
  RunStats uncounted;
  return locate_event(behind, time_s_, f0, t_s, f1, uncounted);
}

void Simulation::deliver_probes_before(double t_s, bool inclusive, SimulationObserver& observer) {
  const double rate = scene_.probes.rate_hz;
  if (!(rate > 0.0) || !observer.wants_probes()) return;
  // An observer that did not want them before: from the next one.
  while (static_cast<double>(next_probe_sample_) / rate <= time_s_ && time_s_ > 0.0) ++next_probe_sample_;
  for (;;) {
    const double tk = static_cast<double>(next_probe_sample_) / rate;
    if (inclusive ? tk > t_s : tk >= t_s) return;
    const Sample s = method_->sample(tk);
    check_invariants(s, limits_);
    observer.on_probe_sample(s);
    ++next_probe_sample_;
  }
}

void Simulation::deliver_shaft_before(double t_s, bool inclusive, SimulationObserver& observer) {
  const double rate = observer.shaft_rate_hz();
  if (!(rate > 0.0)) return;
  const FlexibleRotorModel* rotor = method_->flexible_rotor();
  if (rotor == nullptr) return;
  while (static_cast<double>(next_shaft_sample_) / rate <= time_s_ && time_s_ > 0.0) ++next_shaft_sample_;
  for (;;) {
    const double tk = static_cast<double>(next_shaft_sample_) / rate;
    if (inclusive ? tk > t_s : tk >= t_s) return;
    const Sample s = method_->sample(tk);
    check_invariants(s, limits_);
    shaft_.t_s = tk;
    rotor->node_displacements(s.kin.rotor_pos, method_->modal_state(tk), shaft_.node_displacement_m);
    for (const Vec2& u : shaft_.node_displacement_m) {
      if (!u.allFinite()) {
        throw MethodFailure(FailureClass::kInvariantViolated, tk, "invariant violated: non-finite node displacement");
      }
    }
    observer.on_shaft_sample(shaft_);
    ++next_shaft_sample_;
  }
}

std::vector<double> Simulation::shaft_node_z_m() const {
  const FlexibleRotorModel* rotor = method_->flexible_rotor();
  return rotor == nullptr ? std::vector<double>() : rotor->rotor().node_z_m;
}

Simulation::ContactPoint Simulation::contact_point() const {
  const FlexibleRotorModel* rotor = method_->flexible_rotor();
  const ModelParameters& p = scene_.model;
  ContactPoint c;
  c.mass_kg = rotor == nullptr ? p.rotor_mass_kg : rotor->rotor().station_mass_kg;
  c.effective_mass_kg =
      p.stator_model == StatorModel::kRigid ? c.mass_kg : 1.0 / (1.0 / c.mass_kg + 1.0 / p.stator_mass_kg);
  c.contact_mode_rad_per_s = std::sqrt(p.contact_stiffness_N_per_m / c.effective_mass_kg);
  c.contact_damping_N_s_per_m =
      p.contact_damping_N_s_per_m > 0.0
          ? p.contact_damping_N_s_per_m
          : 2.0 * contact_damping_ratio(p) * std::sqrt(p.contact_stiffness_N_per_m * c.effective_mass_kg);
  return c;
}

Simulation::Reduction Simulation::reduction() const {
  const FlexibleRotorModel* rotor = method_->flexible_rotor();
  if (rotor == nullptr) return Reduction();
  return Reduction{rotor->rotor().planar_modes, rotor->truncation()};
}

int Simulation::shaft_station_node() const {
  const FlexibleRotorModel* rotor = method_->flexible_rotor();
  return rotor == nullptr ? -1 : rotor->rotor().station_node;
}

void Simulation::deliver_until(double t_s, SimulationObserver& observer) {
  const double rate = scene_.output_rate_hz;
  for (;;) {
    const double tk = static_cast<double>(next_sample_) / rate;
    if (tk > t_s) break;
    deliver_marks_before(tk, false, observer);
    deliver_probes_before(tk, false, observer);
    deliver_shaft_before(tk, false, observer);
    for (auto it = step_events_.begin(); it != step_events_.end();) {
      if (it->t_s < tk) {
        count_and_deliver(*it, observer);
        it = step_events_.erase(it);
      } else {
        ++it;
      }
    }
    const Sample s = method_->sample(tk);
    check_invariants(s, limits_);  // a sample that breaks one is never delivered
    observer.on_sample(s);
    ++next_sample_;
  }
  deliver_marks_before(t_s, true, observer);
  deliver_probes_before(t_s, true, observer);
  deliver_shaft_before(t_s, true, observer);
  for (auto it = step_events_.begin(); it != step_events_.end();) {
    if (it->t_s <= t_s) {
      count_and_deliver(*it, observer);
      it = step_events_.erase(it);
    } else {
      ++it;
    }
  }
  time_s_ = t_s;
}

bool Simulation::advance_to(double t_s, SimulationObserver& observer) {
  if (failure_) return false;
  const double target = std::min(t_s, scene_.end_time_s);
  const auto wall_start = std::chrono::steady_clock::now();
  const double wall_before_s = method_->stats().wall_time_s;
  try {
    while (time_s_ < target) {
      // The wall budget, read every 256 passes of this loop (a clock read
      // costs a tenth of a step; this keeps it off the hot path), counted
      // across calls: a node advances a few steps a call, and a count that
      // restarted every call never reached the clock.
      if (++passes_since_clock_ >= kPassesPerClockRead) {
        passes_since_clock_ = 0;
        const double spent =
            wall_before_s + std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
        if (spent > wall_budget_s_) {
          std::ostringstream what;
          what << "wall-time budget max_wall_time_s = " << scene_.solver.max_wall_time_s << " s spent";
          throw MethodFailure(FailureClass::kTimedOut, time_s_, what.str());
        }
      }
      if (method_->step_end() > time_s_) {  // serve the rest of the last step
        ProfileScope scope(scene_.solver.profile_cost ? &method_->mutable_stats().output_time_s : nullptr);
        deliver_until(std::min(method_->step_end(), target), observer);
        continue;
      }
      if (break_due_) {  // the last step ended on a drive discontinuity
        method_->change_segment(t_limit_s_, profile_.segment_at(t_limit_s_));
        break_due_ = false;
      }
      t_limit_s_ = profile_.next_break_after(time_s_);
      method_->step(t_limit_s_, step_events_);
      // Every accepted step is checked at its end before any of its samples
      // or events are delivered.
      check_invariants(method_->sample(method_->step_end()), limits_);
      break_due_ = method_->step_end() >= t_limit_s_;
    }
  } catch (const MethodFailure& f) {
    failure_ = RunFailure{f.failure_class, f.time_s, f.what()};
  }
  method_->mutable_stats().wall_time_s +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return !failure_;
}

RunResult run_scene(const Scene& scene, SimulationObserver& observer) {
  struct Recorder : SimulationObserver {
    SimulationObserver* inner;
    std::vector<ContactEvent> events;
    void on_sample(const Sample& s) override { inner->on_sample(s); }
    void on_event(const ContactEvent& e) override {
      events.push_back(e);
      inner->on_event(e);
    }
    bool wants_keyphasor() const override { return inner->wants_keyphasor(); }
    void on_keyphasor(const Sample& s) override { inner->on_keyphasor(s); }
    bool wants_probes() const override { return inner->wants_probes(); }
    void on_probe_sample(const Sample& s) override { inner->on_probe_sample(s); }
    double shaft_rate_hz() const override { return inner->shaft_rate_hz(); }
    void on_shaft_sample(const ShaftSample& s) override { inner->on_shaft_sample(s); }
  } recorder;
  recorder.inner = &observer;
  Simulation sim(scene);
  sim.advance_to(scene.end_time_s, recorder);
  return {sim.stats(), std::move(recorder.events), sim.failure()};
}

}  // namespace rotor_rub::core
