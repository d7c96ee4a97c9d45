#include "contact/angle_pair.hpp"

#include <cmath>

#if defined(ROTOR_RUB_HAVE_LIBMVEC)
#include <emmintrin.h>
// glibc's vector ABI names (x86-64, SSE2 "b" variant, 2 lanes).
extern "C" __m128d _ZGVbN2v_sin(__m128d);
extern "C" __m128d _ZGVbN2v_cos(__m128d);
#endif

namespace rotor_rub::core {

void unit_vectors(double a, double b, Eigen::Vector2d& ua, Eigen::Vector2d& ub) {
#if defined(ROTOR_RUB_HAVE_LIBMVEC)
  const __m128d angles = _mm_set_pd(b, a);
  alignas(16) double s[2], c[2];
  _mm_store_pd(s, _ZGVbN2v_sin(angles));
  _mm_store_pd(c, _ZGVbN2v_cos(angles));
  ua = Eigen::Vector2d(c[0], s[0]);
  ub = Eigen::Vector2d(c[1], s[1]);
#else
  ua = Eigen::Vector2d(std::cos(a), std::sin(a));
  ub = Eigen::Vector2d(std::cos(b), std::sin(b));
#endif
}

}  // namespace rotor_rub::core
