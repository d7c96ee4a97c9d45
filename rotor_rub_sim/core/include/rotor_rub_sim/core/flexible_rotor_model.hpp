/// @file
/// The reduced flexible rotor's free forces (rotor_reduction.hpp) in the
/// form the contact methods take the Jeffcott's (model.hpp): the force on the
/// rub station, a point of mass m_st, and the accelerations of the modal
/// coordinates, which no contact force reaches. The building block of the
/// methods' seam (docs/rotors.md); tested on its own against the unbalance
/// response.
///
/// In q = [u, xi] (M = diag(m_st I, I)):
///   M q'' = -K q - (C + w G) q' + f(phi, w, A) + [F_contact; 0],
///   f = w^2 (a cos phi + b sin phi) + A (a sin phi - b cos phi),
/// a and b the unbalances' forces (projected) at spin angle 0 and a quarter
/// turn on, per unit w^2: each unbalance m e at angle beta pushes its node by
/// m e (w^2 (cos, sin) + A (sin, -cos))(phi + beta), the Jeffcott's law.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "rotor_rub_sim/core/model.hpp"
#include "rotor_rub_sim/core/rotor_reduction.hpp"
#include "rotor_rub_sim/core/speed_profile.hpp"

namespace rotor_rub::core {

class FlexibleRotorModel {
 public:
  /// Throws std::invalid_argument for an unbalance on no node.
  FlexibleRotorModel(const ReducedRotor& rotor, const std::vector<RotorUnbalance>& unbalances);

  int modal_size() const { return static_cast<int>(k_.rows()) - 2; }
  double station_mass_kg() const { return station_mass_kg_; }
  const ReducedRotor& rotor() const { return rotor_; }

  struct FreeLoads {
    Vec2 station_N = Vec2::Zero();  ///< every force on the station but the contact's [N]
    Eigen::VectorXd modal_acc;      ///< xi'' [sqrt(kg) m / s^2] (M = I there)
  };
  /// At the station's position u and velocity u_dot [m, m/s], the modal
  /// coordinates xi, xi_dot (modal_size() each, else std::invalid_argument),
  /// and the drive d. modal_acc is resized once. Not thread-safe: a work
  /// space is kept in the model (one model per run, as the methods hold theirs).
  void free_loads(const Vec2& u, const Vec2& u_dot, const Eigen::VectorXd& xi, const Eigen::VectorXd& xi_dot,
                  const DriveState& d, FreeLoads& out) const;

 private:
  ReducedRotor rotor_;
  double station_mass_kg_;
  Eigen::MatrixXd k_;                      // K
  Eigen::MatrixXd c_, g_;                  // C, G
  Eigen::VectorXd a_, b_;                  // the unbalances at spin angle 0 and pi/2, per unit w^2 [kg m]
  mutable Eigen::VectorXd q_, q_dot_, f_;  // work space: no allocation per call
};

}  // namespace rotor_rub::core
