/// @file
/// A periodic orbit's branch in the speed (periodic_orbit.hpp's orbits of
/// the Jeffcott's rub) by pseudo-arclength continuation of the shooting's
/// fixed point: the unknowns (y, w / w0), y the section's state in units of
/// C and C w (in contact, its coordinates on the bore's tangent space, or
/// the stick's, at the branch's last point, projected back onto the bore);
/// the residual y(nT) - y (in contact, in those coordinates); its Jacobian
/// [M - I, dR/dw] (in contact B^T (M - I) P, B the chart, P the projected
/// state's derivative), M the
/// exact monodromy, the speed's column by central differences of two shots;
/// a tangent predictor and a Newton corrector on the hyperplane normal to
/// the tangent. Along the branch:
/// * folds where dw/ds changes sign (a multiplier passes +1),
/// * period doublings where det(M + I) changes sign (a real multiplier
///   passes -1),
/// * Neimark-Sacker points where the count of complex multipliers outside
///   the unit circle changes (a pair crosses it),
/// each located by regula falsi along the arclength. At a period doubling
/// the branch of twice the period leaves along the multiplier's
/// eigenvector: continue_period_doubled switches onto it.
///
/// A branch's orbits keep the events of its start (their kinds in order):
/// where they change (an impact appears at a grazing, a contact phase
/// begins), the branch is nonsmooth and the trace ends there, said in `end`,
/// as it ends where a slip comes to rest tangentially or a chattering
/// sequence. The section moves away from the events as they move; a start
/// whose section lies in a contact is taken again at a section in free
/// flight where the orbit has one; an orbit that never leaves the bore (the
/// full rub, a stick-slip on the bore) is traced on the bore's tangent space
/// (the full rub's branch is full_rub_continuation.hpp's too). Where a
/// doubled branch turns back onto the orbit of half its period (its
/// doubling, seen from the doubled side), the trace ends. Tests:
/// test_orbit_continuation.cpp.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "rotor_rub_sim/core/full_rub_continuation.hpp"
#include "rotor_rub_sim/core/periodic_orbit.hpp"

namespace rotor_rub::core {

/// What a branch is traced in: the speed (the default: `model` empty), or a
/// number the scene's model depends on at a constant speed, `model` giving
/// the model at a value (rotor_rub_orbits builds it from a scene key; a
/// value it refuses ends the trace). The settings' min_speed_rad_per_s and
/// max_speed_rad_per_s bound the parameter's values, in its own unit.
struct ContinuationParameter {
  std::string name = "speed";  ///< in messages: "speed", or the key
  std::string unit = "rad/s";  ///< see name ("" where the name says it, as the keys do)
  std::function<ModelParameters(double)> model;
};

enum class OrbitBifurcationKind { kFold, kPeriodDoubling, kNeimarkSacker };
/// "fold", "period_doubling", "neimark_sacker".
const char* to_string(OrbitBifurcationKind kind);

/// A bifurcation located on a branch, with its orbit there.
struct OrbitBifurcation {
  OrbitBifurcationKind kind = OrbitBifurcationKind::kFold;
  double speed_rad_per_s = 0.0;
  double parameter = 0.0;  ///< the continuation parameter's value (the speed's by default)
  PeriodicOrbit orbit;
  std::size_t after_point = 0;  ///< between the branch's points after_point and after_point + 1
};

struct OrbitBranch {
  std::vector<PeriodicOrbit> points;  ///< in the order traced (each knows its speed)
  std::vector<OrbitBifurcation> bifurcations;
  std::string end;  ///< what stopped the trace
};

/// The branch through `start` (find_periodic_orbit's), one direction per
/// call (settings.increasing_speed: the parameter's), in `parameter` (the
/// speed by default; a key's: p is the model at start_value, the key's value
/// at the start), its values in the settings' range. The orbits' settings are `orbit` (periods and
/// section: the start's). Throws std::invalid_argument for an empty range
/// or a start outside it, OrbitError where a start in contact that flies
/// is not found again at a section in free flight.
OrbitBranch continue_orbit(const ModelParameters& p, const PeriodicOrbit& start, const ContinuationSettings& settings,
                           const OrbitSettings& orbit = {}, const ContinuationParameter& parameter = {},
                           double start_value = 0.0);

/// The branch of twice the period born at a period doubling `pd` (a
/// bifurcation of kind kPeriodDoubling), traced from it away from the
/// branch of the single period; its first point is the doubled orbit's
/// nearest to pd. Throws OrbitError when the corrector falls back onto the
/// single period's orbit.
OrbitBranch continue_period_doubled(const ModelParameters& p, const OrbitBifurcation& pd,
                                    const ContinuationSettings& settings, const OrbitSettings& orbit = {},
                                    const ContinuationParameter& parameter = {});

}  // namespace rotor_rub::core
