/// @file
/// The synchronous full annular rub at the rub station of a flexible rotor
/// (fe_rotor.hpp), in closed form through the station's receptance: the
/// Jeffcott's quadratic in the normal force N (steady_response.hpp)
/// generalised. Derivation (docs/rotor_theory.md): in complex notation z = x + i y,
/// for an isotropic rotor (bearings with kxx = kyy, kxy = -kyx and the same
/// for damping) a forward force turning at w gives a forward response. The
/// station then moves as z_r = U0 - h N (1 + i f) n, U0 the unbalances'
/// response there, h the station's forward receptance (its response to a
/// unit forward force at itself), n the contact normal turning at w, and the
/// friction f N against the forward sliding (the rotor's surface sliding
/// forward at w (C + R_r)). The stator: z_s = h_s N (1 + i f) n, h_s =
/// 1 / (k_s - m_s w^2 + i c_s w) (0 when rigid). The contact z_r - z_s = C n
/// gives U0 = n (C + N g), g = (1 + i f)(h + h_s): |C + N g| = |U0|, a
/// quadratic in N, and n = U0 / (C + N g).
#pragma once

#include <complex>
#include <vector>

#include "rotor_rub_sim/core/fe_rotor.hpp"

namespace rotor_rub::core {

struct StationStator {
  bool rigid = true;
  double mass_kg = 0.0, stiffness_N_per_m = 0.0, damping_N_s_per_m = 0.0;  ///< elastic only
};

struct FlexibleFullRub {
  double normal_force_N = 0.0;
  std::complex<double> station_m, stator_m;  ///< z at spin angle 0
  Eigen::VectorXcd response;                 ///< every FE DOF: q = Re(response e^{i w t})
};

/// Every full rub branch at speed w with N > 0, the larger N first. Throws
/// std::invalid_argument naming the problem when the rotor is not isotropic
/// (its orbits are not circles), or a node is out of range.
std::vector<FlexibleFullRub> synchronous_full_rub(const RotorMatrices& m, int station_node,
                                                  const std::vector<RotorUnbalance>& unbalances,
                                                  const StationStator& stator, double clearance_m,
                                                  double friction_coefficient, double w_rad_per_s);

}  // namespace rotor_rub::core
