/// @file
/// Periodic orbits in the frame turning with the shaft. A Jeffcott scene
/// without gravity and with its stator centred is isotropic: its forcing, the
/// unbalance, is constant in the frame turning at the speed w, where the
/// flow is autonomous. A motion that repeats there after its own period T_r
/// (not a multiple of 2 pi / w: quasi-periodic in the casing, as the paper
/// scene's partial rub on a run-down) is a fixed point of
///   y -> R(-w T_r) y(T_r),
/// R(a) turning each planar pair of the state (positions, velocities) by a:
/// Newton on (y, T_r) with the phase condition F . (y - y_g) = 0 (F the
/// turning frame's field f - w J y at the guess y_g: the section through the
/// guess across the flow), its Jacobian [R Phi - I, R (f - w J y)(T_r); F, 0]
/// from periodic_orbit.hpp's exact Phi through the events. The monodromy
/// M = R(-w T_r) Phi has the trivial multiplier 1 (the flow's own
/// direction f: M f = f), kept apart; the orbit's multipliers are the
/// section's map's, (I - f f^T / |f|^2) M on the hyperplane across f. The
/// section lies in free flight. Tests: test_turning_orbit.cpp.
#pragma once

#include <Eigen/Core>

#include "rotor_rub_sim/core/parameters.hpp"
#include "rotor_rub_sim/core/periodic_orbit.hpp"

namespace rotor_rub::core {

/// A start for find_turning_orbit: a state in free flight at time_s, and
/// its period guess.
struct TurningGuess {
  Eigen::VectorXd state;  ///< the free layout's [m, m/s]
  double time_s = 0.0;
  double period_s = 0.0;
};

/// The guess from the flow from x at t_s over `periods` forcing periods:
/// where its last impacts' closing velocities repeat every m impacts, the
/// period is the time of the last m impacts and the state the one in the
/// middle of the longest flight among them. OrbitError where they do not repeat (the
/// motion has not settled, or is not periodic in the turning frame) or
/// there is no impact; std::invalid_argument for a scene that is not
/// isotropic (check_turning_scene).
TurningGuess turning_orbit_guess(const ModelParameters& p, double w_rad_per_s, const Eigen::VectorXd& x, double t_s,
                                 int periods, const OrbitSettings& settings = {});

/// The orbit near the guess: PeriodicOrbit with turning set, period_s T_r,
/// state the state at section_angle_rad / w (the guess's time in the
/// forcing period), monodromy the full M, multipliers the section's map's
/// (trivial_multiplier f^T M f / |f|^2 apart). Throws OrbitError where Newton does not
/// converge, the section leaves free flight or the orbit grazes.
PeriodicOrbit find_turning_orbit(const ModelParameters& p, double w_rad_per_s, const TurningGuess& guess,
                                 const OrbitSettings& settings = {});

/// std::invalid_argument naming the key where the scene is not autonomous
/// in the turning frame (gravity, an offset stator), with check_scene's.
void check_turning_scene(const ModelParameters& p, double w_rad_per_s, const OrbitSettings& settings);

}  // namespace rotor_rub::core
