/// @file
/// Classic RK4's stability bound: the largest fixed step h with
/// |R(h lambda)| <= 1, R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24, for every
/// eigenvalue lambda of a linear(ised) system, and that bound for the
/// penalty contact (contact_law.hpp) on the Jeffcott and on a flexible
/// rotor. Above it the clamp keeps the state bounded but the contact
/// chatters: a wrong answer, so validate_scene() refuses such a step.
#pragma once

#include <complex>

#include "rotor_rub_sim/core/flexible_rotor_model.hpp"
#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

/// The largest h [s] with |R(s lambda)| <= 1 for every s in (0, h]: on the
/// negative real axis 2.785 / |lambda|, on the imaginary one 2 sqrt(2) /
/// |lambda|; between them down to 2.616 / |lambda| (at 122 degrees), so no
/// one radius serves every damping ratio. An eigenvalue with Re lambda >= 0
/// (an undamped mode, or one the physics itself grows) gets the imaginary
/// axis's bound; lambda = 0 none (infinity).
double rk4_stable_step_s(std::complex<double> lambda);

/// The penalty contact's RK4 bound on the Jeffcott [s], from its contact
/// mode's eigenvalues in closed form: omega_c (-zeta +- i sqrt(1 - zeta^2))
/// (underdamped) or -omega_c (zeta +- sqrt(zeta^2 - 1)) (zeta >= 1),
/// omega_c = sqrt(k_c / m_eff); with friction also the tangential damper's
/// -c_t W_tt while the contact creeps: -2 omega_c, times 1 + (R_r + e)^2
/// m_eff / J_G under a motor drive (the spin shares the tangential impulse,
/// model.hpp); under a motor the speed controller's J_G s^2 + K_p s + K_i
/// and, in the torque limit, its anti-windup's -K_i / K_p. The rotor's and
/// stator's own springs (k_r, k_s << k_c) are left out: they move it by
/// k / k_c; so is the unbalance's lever along the normal (e u . n, of order
/// m e^2 / J_G of the contact's mobility).
double rk4_stable_step_s(const JeffcottModel& m);

/// The penalty contact's RK4 bound on a flexible rotor [s]: the smallest of
/// rk4_stable_step_s over the eigenvalues of the reduced rotor (M, K, C and
/// Omega G), the elastic stator and, under a motor drive, the spin with its
/// speed controller (K_p a damper, K_i a spring on the spin angle; in the
/// torque limit the anti-windup's -K_i / K_p) (its inertia
/// rotor_polar_inertia_kg_m2, turned by the friction at the contact,
/// at its lowest over the spin angle (J - max h^T M^-1 h, with the station's
/// lever R_r + sqrt(max h^T M^-1 h / m_st): the Jeffcott's R_r + e,
/// validate_flexible_spin's bound), linearised in sustained contact with
/// the method's own law (PenaltyLaw on
/// the station, station_parameters): the spring and damper along the
/// normal, and the friction in each of its regimes (the tangential damper in
/// stick; the cone's f F_n in slip, either way). Taken with the normal along
/// x and along y (the bearings may differ) and at speeds 0 and
/// max_speed_rad_per_s (the gyroscopic moments grow with speed; the limit
/// of any speed command). Left out, as on the Jeffcott: the unbalances'
/// lever along the normal (h_u . n reaching the spin), of order max h^T
/// M^-1 h / J_eff of the contact's mobility. scene_model: the scene's
/// parameters.
double flexible_rk4_stable_step_s(const FlexibleRotorModel& rotor, const ModelParameters& scene_model,
                                  double max_speed_rad_per_s);

}  // namespace rotor_rub::core
