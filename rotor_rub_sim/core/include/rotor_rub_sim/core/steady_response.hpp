// Closed forms of the model's steady motions at a constant speed w, for tests,
// charts and the bifurcation tool's classes. Derivations: docs/steady_response.md.
// Complex notation: a position (x, y) is x + i y; at a keyphasor (spin angle
// 2 pi k) the unbalance force m e w^2 points along beta (unbalance_phase_rad,
// 0: +x), so these are the Poincare points of the period-1 motions.
#pragma once

#include <complex>
#include <vector>

#include "rotor_rub_sim/core/parameters.hpp"

namespace rotor_rub::core {

// Without contact and gravity: z = m e w^2 e^(i beta) / (k - m w^2 + i c w) [m].
std::complex<double> unbalance_response_m(const ModelParameters& p, double w_rad_per_s);

// Synchronous full annular rub: rotor and stator whirl forward at w, in
// contact all the time, sliding forward at w (C + R_r) (so the friction is
// f N against it). Rotor z_r, stator z_s with |z_r - z_s| = C (rigid contact),
// normal force N > 0. Gravity must be 0 (it breaks the circular symmetry).
struct FullRub {
  std::complex<double> rotor_m, stator_m;
  double normal_force_N = 0.0;
};
// Every solution with N > 0: none (no such branch at w), one (when the free
// orbit alone is larger than C) or two, the larger normal force first. With the penalty method the rotor overlaps the
// stator by N / k_c more (not included).
std::vector<FullRub> synchronous_full_rub(const ModelParameters& p, double w_rad_per_s);
// The discriminant of the full rub's equation at w, scaled to ((N1 - N2) / 2)^2
// [N^2] of its two roots: negative where no full rub exists, 0 where the two
// meet. Where the larger root is positive, a zero is a fold of the branch
// (test_full_rub_continuation.cpp).
double full_rub_discriminant_N2(const ModelParameters& p, double w_rad_per_s);

// The full rub's equation in every model: the real N > 0 with |a + N b| = r,
// the larger first, a double root once.
std::vector<double> positive_circle_roots(std::complex<double> a, std::complex<double> b, double r);

// The lowest speed at which the steady unbalance orbit (offset by the static
// sags under gravity, m_r g / k_r - m_s g / k_s) reaches the clearance:
// |z(w)| + |sag offset| = C, solved by TOMS 748 below the amplitude's peak.
// Infinity when the orbit never reaches it; NaN when gravity acts on a support
// of zero stiffness (no static position).
double rub_onset_speed_rad_per_s(const ModelParameters& p);

}  // namespace rotor_rub::core
