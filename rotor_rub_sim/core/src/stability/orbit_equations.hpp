// The fixed point's equations of an orbit's branch (orbit_continuation.cpp):
// the shooting residual in the section's state (in a chart of the bore's
// tangent space in contact) and the parameter, its Jacobian, the tangent
// and the corrector.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "orbit_shot.hpp"
#include "rotor_rub_sim/core/orbit_continuation.hpp"

namespace rotor_rub::core {

// The parameter column's difference step, in units of the start's value:
// the column carries the shot's error over the step (about the tolerance 1e-11
// over 1e-6: the adaptive steps' sequence moves with the speed), which only
// the tangent's direction sees.
inline constexpr double kParameterStep = 1e-6;
// The chart's difference step (in C and C w): the projection onto the bore
// is smooth, so its truncation (1e-12) and rounding (1e-10) are both small.
inline constexpr double kChartStep = 1e-6;
// The corrector's iterations before a step is halved.
inline constexpr int kMaxCorrections = 8;

inline std::vector<OrbitEvent::Kind> event_kinds(const std::vector<OrbitEvent>& events) {
  std::vector<OrbitEvent::Kind> out;
  for (const OrbitEvent& e : events) out.push_back(e.kind);
  return out;
}

// The fixed point's equations in Y = (z, v / v0), v the parameter (the
// speed, or a key's value at the constant speed w), v0 its start's value,
// z the section's state in a chart: in free flight the scaled state y
// itself; in contact (an orbit that never leaves the bore) coordinates on
// the bore's tangent space (the stick's, sticking) at a point of the branch,
// the state that point plus chart z projected back onto the bore (and the
// stick), the residual the end's difference from it in the chart: the
// Jacobian's state block is B^T (M - I) P (B the chart, P the projected
// state's derivative in z, B itself at the chart's point).
class OrbitEquations {
 public:
  using Vector = Eigen::VectorXd;
  OrbitEquations(const ModelParameters& p, const OrbitSettings& s, const ContinuationParameter& parameter, double v0,
                 double w, const std::vector<OrbitEvent>& events)
      : p_(&p), s_(s), parameter_(&parameter), v0_(v0), w_(w), kinds_(event_kinds(events)) {}
  const OrbitSettings& settings() const { return s_; }
  const ContinuationParameter& parameter() const { return *parameter_; }
  // The same equations at other settings (a section moved) and events, in
  // free flight's chart.
  OrbitEquations with(const OrbitSettings& s, const std::vector<OrbitEvent>& events) const {
    return OrbitEquations(*p_, s, *parameter_, v0_, w_, events);
  }
  // The same equations charted at the scaled state y at the section, in
  // its regime (0 free, 1 sliding, 2 sticking).
  OrbitEquations charted(const RubFlow& flow, const Vector& y, int regime) const {
    OrbitEquations g = *this;
    g.regime_ = regime;
    g.origin_ = y;
    g.chart_ =
        regime == 0 ? Eigen::MatrixXd() : flow.tangent_basis(s_.section_angle_rad / flow.speed(), y, regime == 2);
    return g;
  }
  // Charted at orbit o (its tangent basis: the coordinates of its monodromy).
  OrbitEquations at(const PeriodicOrbit& o) const {
    const RubFlow flow = flow_at(o.parameter);
    OrbitEquations g = with(s_, {});
    g.kinds_ = kinds_;
    g.regime_ = o.starts_in_stick ? 2 : o.starts_in_contact ? 1 : 0;
    if (g.regime_ != 0) {
      g.origin_ = flow.scaled(o.state);
      g.chart_ = o.tangent_basis;
    }
    return g;
  }
  bool in_contact() const { return regime_ != 0; }
  // A state-space vector in the chart's coordinates, and back.
  Vector coordinates(const Vector& dy) const { return regime_ == 0 ? dy : Vector(chart_.transpose() * dy); }
  Vector state_direction(const Vector& dz) const { return regime_ == 0 ? dz : Vector(chart_ * dz); }

  double start_value() const { return v0_; }
  double value(const Vector& Y) const { return Y(Y.size() - 1) * v0_; }
  bool in_speed() const { return !parameter_->model; }
  double speed_at(double v) const { return in_speed() ? v : w_; }
  double speed(const Vector& Y) const { return speed_at(value(Y)); }
  // The model at a value: a value the parameter refuses ends the trace.
  ModelParameters model_at(double v) const {
    if (in_speed()) return *p_;
    try {
      return parameter_->model(v);
    } catch (const std::exception& e) {
      throw OrbitError(parameter_->name + " " + std::to_string(v) + " is refused: " + e.what());
    }
  }
  RubFlow flow_at(double v) const {
    const ModelParameters p = model_at(v);
    return RubFlow(p, speed_at(v), settle_apex_m(p, s_));
  }
  // "52.98 rad/s", "friction_coefficient 0.31": a value in messages.
  std::string describe(double v) const {
    if (in_speed()) return std::to_string(v) + " rad/s";
    return parameter_->name + " " + std::to_string(v) + (parameter_->unit.empty() ? "" : " " + parameter_->unit);
  }

  // The scaled state at the section of Y.
  Vector state(const RubFlow& flow, const Vector& Y) const {
    const Vector z = Y.head(Y.size() - 1);
    if (regime_ == 0) return z;
    Vector y = origin_ + chart_ * z;
    flow.project_to_bore(y);
    if (regime_ == 2) flow.project_to_stick(s_.section_angle_rad / flow.speed(), y);
    return y;
  }
  // One shot from Y's section over the orbit's periods; OrbitError where the
  // events or the section's regime differ from the branch's.
  OrbitShot shot(const Vector& Y, bool with_jacobian) const {
    const double w = speed(Y);
    const ModelParameters p = model_at(value(Y));
    check_scene(p, w, s_);
    const RubFlow flow(p, w, settle_apex_m(p, s_));
    const double t0 = s_.section_angle_rad / w;
    OrbitShot out = shoot(flow, state(flow, Y), t0, t0 + s_.periods * flow.period(), s_, with_jacobian);
    const int regime = out.starts_in_stick ? 2 : out.starts_in_contact ? 1 : 0;
    if (regime != regime_ || out.ends_in_contact != out.starts_in_contact || out.ends_in_stick != out.starts_in_stick) {
      throw OrbitError("the section's regime (free flight, sliding or sticking on the bore) changes near " +
                       describe(value(Y)));
    }
    if (event_kinds(out.events) != kinds_) {
      throw OrbitError("the orbit's events change at the trial " + describe(value(Y)) +
                       " (a grazing: an impact or a contact phase appears or ends)");
    }
    return out;
  }
  Vector residual(const Vector& Y) const {
    const OrbitShot s = shot(Y, false);
    return coordinates(s.end - s.start);
  }
  // [R, d R / d Y] at Y (m x (m + 1)).
  Eigen::MatrixXd jacobian(const Vector& Y, Vector* r = nullptr) const {
    const int m = static_cast<int>(Y.size()) - 1;
    const OrbitShot s = shot(Y, true);
    if (r != nullptr) *r = coordinates(s.end - s.start);
    Eigen::MatrixXd j(m, m + 1);
    if (regime_ == 0) {
      j.leftCols(m) = s.jacobian - Eigen::MatrixXd::Identity(m, m);
    } else {
      // B^T (M - I) d state / d z: the chart B at its own point, the
      // projection's derivative (central differences, smooth) elsewhere.
      const RubFlow flow = flow_at(value(Y));
      const int n = static_cast<int>(s.start.size());
      Eigen::MatrixXd dz(n, m);
      Vector zp = Y, zm = Y;
      for (int i = 0; i < m; ++i) {
        zp(i) += kChartStep;
        zm(i) -= kChartStep;
        dz.col(i) = (state(flow, zp) - state(flow, zm)) / (2.0 * kChartStep);
        zp(i) = zm(i) = Y(i);
      }
      j.leftCols(m) = chart_.transpose() * (s.jacobian - Eigen::MatrixXd::Identity(n, n)) * dz;
    }
    Vector up = Y, down = Y;
    up(m) += kParameterStep;
    down(m) -= kParameterStep;
    j.col(m) = (residual(up) - residual(down)) / (2.0 * kParameterStep);
    return j;
  }
  Vector tangent(const Vector& Y, const Vector& previous) const {
    const int n = static_cast<int>(Y.size()) - 1;
    Eigen::MatrixXd a(n + 1, n + 1);
    a.topRows(n) = jacobian(Y);
    a.row(n) = previous.transpose();
    Vector rhs = Vector::Zero(n + 1);
    rhs(n) = 1.0;
    return a.fullPivLu().solve(rhs).normalized();
  }
  // Newton from Y_pred on the hyperplane t . (Y - Y_pred) = 0.
  bool correct(const Vector& Y_pred, const Vector& t, Vector& Y, int& iterations) const {
    const int n = static_cast<int>(Y_pred.size()) - 1;
    Y = Y_pred;
    for (iterations = 0; iterations < kMaxCorrections; ++iterations) {
      const Vector r0 = residual(Y);  // one shot without the Jacobian: often the last
      if (!r0.allFinite()) return false;
      if (r0.lpNorm<Eigen::Infinity>() < s_.newton_tolerance) return true;
      Vector r;
      Eigen::MatrixXd a(n + 1, n + 1);
      a.topRows(n) = jacobian(Y, &r);
      a.row(n) = t.transpose();
      Vector rhs(n + 1);
      rhs.head(n) = -r;
      rhs(n) = -t.dot(Y - Y_pred);
      Y += a.fullPivLu().solve(rhs);
    }
    return false;
  }
  PeriodicOrbit orbit(const Vector& Y, int iterations = 0) const {
    const double w = speed(Y);
    const ModelParameters p = model_at(value(Y));
    const RubFlow flow(p, w, settle_apex_m(p, s_));
    const OrbitShot s = shot(Y, true);
    check_grazing(s.closest_miss);
    PeriodicOrbit o;
    o.speed_rad_per_s = w;
    o.parameter = value(Y);
    o.periods = s_.periods;
    o.period_s = s_.periods * flow.period();
    o.section_angle_rad = s_.section_angle_rad;
    o.state = flow.physical(s.start);
    o.keyphasor_states = keyphasor_states(flow, s.start, s_.section_angle_rad / w, s_);
    o.events = s.events;
    // In contact, on the tangent space at the point itself (the chart's is
    // a neighbour's).
    o.starts_in_contact = s.starts_in_contact;
    o.starts_in_stick = s.starts_in_stick;
    o.tangent_basis = regime_ == 0 ? Eigen::MatrixXd::Identity(s.jacobian.rows(), s.jacobian.cols())
                                   : flow.tangent_basis(s_.section_angle_rad / w, s.start, regime_ == 2);
    o.monodromy = o.tangent_basis.transpose() * s.jacobian * o.tangent_basis;
    o.multipliers = sorted_eigenvalues(o.monodromy);
    o.residual = (s.end - s.start).lpNorm<Eigen::Infinity>();
    o.newton_iterations = iterations;
    o.slowest_impact = s.slowest_impact;
    o.closest_miss = s.closest_miss;
    return o;
  }
  // The unknowns of an orbit (o.parameter its value) in this chart.
  Vector unknowns(const PeriodicOrbit& o) const {
    const RubFlow flow = flow_at(o.parameter);
    const Vector y = flow.scaled(o.state);
    const Vector z = coordinates(regime_ == 0 ? y : Vector(y - origin_));
    Vector Y(z.size() + 1);
    Y.head(z.size()) = z;
    Y(z.size()) = o.parameter / v0_;
    return Y;
  }

 private:
  const ModelParameters* p_;
  OrbitSettings s_;
  const ContinuationParameter* parameter_;
  double v0_, w_;
  std::vector<OrbitEvent::Kind> kinds_;
  int regime_ = 0;         // the section's: 0 free, 1 sliding, 2 sticking
  Vector origin_;          // the chart's point (scaled), in contact
  Eigen::MatrixXd chart_;  // its orthonormal tangent basis, in contact
};

}  // namespace rotor_rub::core
