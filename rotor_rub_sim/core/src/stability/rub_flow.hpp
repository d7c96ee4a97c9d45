// The Jeffcott rotor's event-driven flow at a constant speed w in the units
// periodic_orbit.hpp integrates it in: y = (positions / C, velocities /
// (C w)), the free layout's order. Its three fields (free flight; the rotor
// held on the bore sliding, the friction -f F_n s; held on the bore
// sticking, rolling, the friction the stick force that holds v_slide' = 0:
// contact_law.hpp's stick regime), the events' functions, the impact's
// jump, and their Jacobians. The physics is the model's own
// (station_model.hpp, model.hpp, contact_law.hpp): this file only evaluates
// it on a vector.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>

#include "rotor/rotor_model.hpp"
#include "rotor_rub_sim/core/contact_law.hpp"
#include "rotor_rub_sim/core/model.hpp"
#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/periodic_orbit.hpp"

namespace rotor_rub::core {

enum class OrbitRegime { kFree, kContact, kStick };  // kContact: sliding

// A slip this small (in units of C w) at a contact's start or after an
// impact is a stick: the impact law ends a stick at 0 but for the rounding
// of the velocities it adds (of order 1e-16 of them, which are of order 1
// and R_r / C here).
inline constexpr double kStickSlip = 1e-9;

// RubFlow's order is the free layout's, with the indices at run time.
static_assert(FreeLayout<0>::kRotorVel == 2 && FreeLayout<0>::kSize == 4, "a rigid stator's layout");
static_assert(FreeLayout<2>::kStatorPos == 2 && FreeLayout<2>::kRotorVel == 4 && FreeLayout<2>::kStatorVel == 6 &&
                  FreeLayout<2>::kSize == 8,
              "an elastic stator's layout");

class RubFlow {
 public:
  RubFlow(const ModelParameters& p, double w_rad_per_s, double settle_apex_m)
      : model_(p),
        w_(w_rad_per_s),
        C_(p.clearance_m),
        settle_apex_m_(settle_apex_m),
        elastic_(p.stator_model == StatorModel::kElastic),
        n_(elastic_ ? 8 : 4),
        vel_(elastic_ ? 4 : 2) {
    scale_.resize(n_);
    scale_.head(vel_).setConstant(C_);
    scale_.tail(n_ - vel_).setConstant(C_ * w_);
    free_jacobian_ = affine_jacobian();
  }
  int size() const { return n_; }
  double speed() const { return w_; }
  double period() const { return 2.0 * M_PI / w_; }
  const JeffcottModel& model() const { return model_; }

  // Casing-frame state [m, m/s] <-> y (a rigid stator's offset moves the
  // methods' frame: StationModel::frame_shift).
  Eigen::VectorXd scaled(const Eigen::VectorXd& x) const {
    Eigen::VectorXd y = x;
    y.head<2>() -= model_.frame_shift();
    return y.cwiseQuotient(scale_);
  }
  Eigen::VectorXd physical(const Eigen::VectorXd& y) const {
    Eigen::VectorXd x = y.cwiseProduct(scale_);
    x.head<2>() += model_.frame_shift();
    return x;
  }
  // d x / d x0 of the Jacobian in y.
  Eigen::MatrixXd physical_jacobian(const Eigen::MatrixXd& j) const {
    return scale_.asDiagonal() * j * scale_.cwiseInverse().asDiagonal();
  }

  Kinematics kinematics(const Eigen::VectorXd& y) const {
    Kinematics k;
    k.rotor_pos = C_ * y.head<2>();
    k.rotor_vel = C_ * w_ * y.segment<2>(vel_);
    if (elastic_) {
      k.stator_pos = C_ * y.segment<2>(2);
      k.stator_vel = C_ * w_ * y.segment<2>(vel_ + 2);
    }
    return k;
  }
  void store(const Kinematics& k, Eigen::VectorXd& y) const {
    y.head<2>() = k.rotor_pos / C_;
    y.segment<2>(vel_) = k.rotor_vel / (C_ * w_);
    if (elastic_) {
      y.segment<2>(2) = k.stator_pos / C_;
      y.segment<2>(vel_ + 2) = k.stator_vel / (C_ * w_);
    }
  }
  DriveState drive(double t) const { return {w_ * t, w_, 0.0, 0.0}; }

  // The normal force that holds the rotor on the bore, F_n = m_eff delta''
  // without contact force (the friction has no normal share under the
  // prescribed drive), over m_eff C w^2: > 0 pressed.
  double normal_force(double t, const Eigen::VectorXd& y) const {
    const Kinematics k = kinematics(y);
    const DriveState d = drive(t);
    const ContactGeometry g = model_.contact_geometry(k, d);
    return pressing_acceleration(model_, k, d, g) / (C_ * w_ * w_);
  }
  double gap(const Eigen::VectorXd& y) const {  // (delta - C) / C, < 0 apart
    return (y.head<2>() - stator_pos(y)).norm() - 1.0;
  }
  double closing_rate(const Eigen::VectorXd& y) const {  // delta' / (C w), > 0 closing
    const Eigen::Vector2d rel = y.head<2>() - stator_pos(y);
    return rel.normalized().dot(y.segment<2>(vel_) - stator_vel(y));
  }
  double angle_rate(const Eigen::VectorXd& y) const {  // psi' [rad/s], the contact angle's
    const Eigen::Vector2d rel = y.head<2>() - stator_pos(y), v = y.segment<2>(vel_) - stator_vel(y);
    return w_ * (rel.x() * v.y() - rel.y() * v.x()) / rel.squaredNorm();
  }
  double slip(double t, const Eigen::VectorXd& y) const {  // v_slide / (C w)
    return model_.contact_geometry(kinematics(y), drive(t)).sliding_velocity_m_per_s / (C_ * w_);
  }

  // The stick force F_t that holds v_slide' = 0, over m_eff C w^2 (the
  // normal_force()'s units): -m_eff v_slide'(F_t = 0), v_slide' affine in
  // F_t with the slope 1 / m_eff (station_model.hpp's sliding_acceleration).
  double stick_force(double t, const Eigen::VectorXd& y) const {
    const Kinematics k = kinematics(y);
    const DriveState d = drive(t);
    const ContactGeometry g = model_.contact_geometry(k, d);
    const double fn = normal_force(t, y) * model_.effective_mass_kg() * C_ * w_ * w_;
    return -model_.sliding_acceleration(k, g, model_.accelerations(d, g, model_.free_loads(k, d), fn, 0.0)) /
           (C_ * w_ * w_);
  }
  // The friction cone's margin f F_n - |F_t,stick| (the same units): a stick
  // holds while it is >= 0.
  double cone_margin(double t, const Eigen::VectorXd& y) const {
    return model_.parameters().friction_coefficient * normal_force(t, y) - std::abs(stick_force(t, y));
  }

  // dy/dt: in contact the normal force normal_force() and the friction
  // -f F_n slip_sign (sliding) or the stick force (sticking).
  void field(double t, const Eigen::VectorXd& y, OrbitRegime regime, double slip_sign, Eigen::VectorXd& dydt) const {
    const Kinematics k = kinematics(y);
    const DriveState d = drive(t);
    const ContactGeometry g = model_.contact_geometry(k, d);
    const FreeLoads loads = model_.free_loads(k, d);
    double fn = 0.0, ft = 0.0;
    if (regime != OrbitRegime::kFree) {
      fn = model_.effective_mass_kg() *
           StationModel::distance_acceleration(k, g, model_.accelerations(d, g, loads, 0.0, 0.0));
    }
    if (regime == OrbitRegime::kContact) {
      ft = -model_.parameters().friction_coefficient * slip_sign * fn;
    } else if (regime == OrbitRegime::kStick) {
      ft = -model_.effective_mass_kg() * model_.sliding_acceleration(k, g, model_.accelerations(d, g, loads, fn, 0.0));
    }
    const Accelerations a = model_.accelerations(d, g, loads, fn, ft);
    dydt.resize(n_);
    dydt.head(vel_) = w_ * y.tail(n_ - vel_);
    dydt.segment<2>(vel_) = a.rotor / (C_ * w_);
    if (elastic_) dydt.segment<2>(vel_ + 2) = a.stator / (C_ * w_);
  }

  // d(dy/dt)/dy: the free flight's constant; in contact central differences
  // of step kContactStep, whose truncation (of order its square times the
  // field's third derivative, which is of order 1 in these units) and
  // rounding (1e-16 / step) are both near 1e-10.
  static constexpr double kContactStep = 1e-5;
  Eigen::MatrixXd jacobian(double t, const Eigen::VectorXd& y, OrbitRegime regime, double slip_sign) const {
    if (regime == OrbitRegime::kFree) return free_jacobian_;
    Eigen::MatrixXd j(n_, n_);
    Eigen::VectorXd yp = y, ym = y, fp, fm;
    for (int i = 0; i < n_; ++i) {
      yp(i) = y(i) + kContactStep;
      ym(i) = y(i) - kContactStep;
      field(t, yp, regime, slip_sign, fp);
      field(t, ym, regime, slip_sign, fm);
      j.col(i) = (fp - fm) / (2.0 * kContactStep);
      yp(i) = ym(i) = y(i);
    }
    return j;
  }

  // The impact law's jump (contact_law.hpp's apply_impact, the switching
  // method's) at a located touchdown; settles: the rebound settled (plastic).
  Eigen::VectorXd impact(double t, const Eigen::VectorXd& y, bool* settles = nullptr, bool* stuck = nullptr) const {
    Kinematics k = kinematics(y);
    const DriveState d = drive(t);
    const ContactGeometry g = model_.contact_geometry(k, d);
    const ImpactResult r = apply_impact(model_, g, d, settle_apex_m_, model_.free_loads(k, d), k);
    if (settles != nullptr) *settles = r.settles;
    Eigen::VectorXd out = y;
    store(k, out);
    if (stuck != nullptr) *stuck = std::abs(slip(t, out)) < kStickSlip;
    return out;
  }
  // Its Jacobian by central differences, of a step below a hundredth of the
  // closing velocity (every neighbour closes too). The jump is smooth while
  // the impact slides throughout and every neighbour settles or rebounds as
  // the impact itself does: where the settling rule (contact_law.hpp) parts
  // them, or a stick within the impulse (its slide ending before the
  // impulse does), the jump has no derivative and OrbitError says so.
  Eigen::MatrixXd impact_jacobian(double t, const Eigen::VectorXd& y) const {
    const double h = std::min(kContactStep, 1e-2 * closing_rate(y));
    bool settles = false, stuck = false;
    impact(t, y, &settles, &stuck);
    Eigen::MatrixXd j(n_, n_);
    Eigen::VectorXd yp = y, ym = y;
    for (int i = 0; i < n_; ++i) {
      yp(i) = y(i) + h;
      ym(i) = y(i) - h;
      bool sp = false, sm = false, kp = false, km = false;
      const Eigen::VectorXd fp = impact(t, yp, &sp, &kp), fm = impact(t, ym, &sm, &km);
      if (sp != settles || sm != settles) {
        throw OrbitError("an impact at t = " + std::to_string(t) +
                         " s lies at the edge of the settling rule (its rebound settles or not as the state moves "
                         "by a rounding): its jump has no derivative there");
      }
      if (kp != stuck || km != stuck) {
        throw OrbitError("an impact at t = " + std::to_string(t) +
                         " s lies at the edge of a stick (its friction stops the slip or not as the state moves by "
                         "a rounding): its jump has no derivative there");
      }
      j.col(i) = (fp - fm) / (2.0 * h);
      yp(i) = ym(i) = y(i);
    }
    return j;
  }
  // The gap's gradient in y.
  Eigen::RowVectorXd gap_gradient(const Eigen::VectorXd& y) const {
    const Eigen::Vector2d n = (y.head<2>() - stator_pos(y)).normalized();
    Eigen::RowVectorXd h = Eigen::RowVectorXd::Zero(n_);
    h.head<2>() = n.transpose();
    if (elastic_) h.segment<2>(2) = -n.transpose();
    return h;
  }
  Eigen::RowVectorXd closing_rate_gradient(const Eigen::VectorXd& y) const {
    const auto fn = [this](const Eigen::VectorXd& v) {
      Eigen::VectorXd out(1);
      out(0) = closing_rate(v);
      return out;
    };
    return central_jacobian(fn, y);
  }
  Eigen::RowVectorXd slip_gradient(double t, const Eigen::VectorXd& y) const {
    const auto fn = [this, t](const Eigen::VectorXd& v) {
      Eigen::VectorXd out(1);
      out(0) = slip(t, v);
      return out;
    };
    return central_jacobian(fn, y);
  }
  // y on the bore moved onto the stick's manifold (v_slide = 0) by the
  // rotor's tangential velocity.
  void project_to_stick(double t, Eigen::VectorXd& y) const {
    const Eigen::Vector2d n = (y.head<2>() - stator_pos(y)).normalized();
    y.segment<2>(vel_) -= slip(t, y) * Eigen::Vector2d(-n.y(), n.x());
  }
  // y moved onto the bore (delta = C, delta' = 0) along the normal.
  void project_to_bore(Eigen::VectorXd& y) const {
    const Eigen::Vector2d s = stator_pos(y), rel = y.head<2>() - s;
    const Eigen::Vector2d n = rel.normalized();
    y.head<2>() = s + n;
    const double vn = n.dot(y.segment<2>(vel_) - stator_vel(y));
    y.segment<2>(vel_) -= vn * n;
  }
  // An orthonormal basis of the bore's tangent space at y (n - 2 columns):
  // the perturbations that keep the rotor on the bore to first order; with
  // stick, also v_slide = 0 (n - 3 columns).
  Eigen::MatrixXd tangent_basis(double t, const Eigen::VectorXd& y, bool stick) const;

 private:
  Eigen::Vector2d stator_pos(const Eigen::VectorXd& y) const {
    return elastic_ ? Eigen::Vector2d(y.segment<2>(2)) : Eigen::Vector2d::Zero();
  }
  Eigen::Vector2d stator_vel(const Eigen::VectorXd& y) const {
    return elastic_ ? Eigen::Vector2d(y.segment<2>(vel_ + 2)) : Eigen::Vector2d::Zero();
  }
  // The free field is affine in y under the prescribed drive (the shaft's and
  // supports' springs and dampers, the unbalance and gravity in t only):
  // differences of unit steps are its matrix to rounding.
  Eigen::MatrixXd affine_jacobian() const {
    Eigen::MatrixXd j(n_, n_);
    const Eigen::VectorXd y0 = Eigen::VectorXd::Zero(n_);
    Eigen::VectorXd f0, f1, y1 = y0;
    field(0.0, y0, OrbitRegime::kFree, 0.0, f0);
    for (int i = 0; i < n_; ++i) {
      y1(i) = 1.0;
      field(0.0, y1, OrbitRegime::kFree, 0.0, f1);
      j.col(i) = f1 - f0;
      y1(i) = 0.0;
    }
    return j;
  }
  template <class F>
  Eigen::MatrixXd central_jacobian(F&& f, const Eigen::VectorXd& y) const {
    const Eigen::VectorXd f0 = f(y);
    Eigen::MatrixXd j(f0.size(), n_);
    Eigen::VectorXd yp = y, ym = y;
    for (int i = 0; i < n_; ++i) {
      yp(i) = y(i) + kContactStep;
      ym(i) = y(i) - kContactStep;
      j.col(i) = (f(yp) - f(ym)) / (2.0 * kContactStep);
      yp(i) = ym(i) = y(i);
    }
    return j;
  }

  JeffcottModel model_;
  double w_, C_, settle_apex_m_;
  bool elastic_;
  int n_, vel_;
  Eigen::VectorXd scale_;
  Eigen::MatrixXd free_jacobian_;
};

}  // namespace rotor_rub::core
