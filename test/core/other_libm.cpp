// A libm with other last bits, for LD_PRELOAD: every transcendental function
// the core calls (the scalar ones and libmvec's two-lane sin and cos) returns
// the system's result moved by one ulp up, one ulp down, or not at all, as a
// hash of the arguments and ROTOR_RUB_LIBM_SEED decides (the same arguments,
// the same answer, as from any libm). That is what another libm build is
// allowed to do: glibc promises no correct rounding, and other libms round
// these functions differently. Exact results stay exact (0, +-1, integers,
// infinities, NaN, an exact power), atan2 stays within [-pi, pi]; sqrt is
// correctly rounded everywhere and left alone. (Where libmvec itself falls
// back to the scalar sin or cos, a lane is moved twice: still one libm.)
//
// test_golden.cpp runs under it (CMakeLists.txt: golden_other_libm): the
// golden runs must hold across libm builds. At exit it says on stderr how
// many results it moved, so a run can show it was in effect.
#include <dlfcn.h>
#include <emmintrin.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <utility>

namespace {

std::uint64_t g_seed = 1;
unsigned long g_results = 0, g_moved = 0;
__attribute__((destructor)) void report() {
  std::fprintf(stderr, "other_libm: seed %llu: %lu of %lu results moved by one ulp\n",
               static_cast<unsigned long long>(g_seed), g_moved, g_results);
}

std::uint64_t bits_of(double x) {
  std::uint64_t u;
  std::memcpy(&u, &x, sizeof u);
  return u;
}
// splitmix64's finaliser: neighbouring arguments get unrelated decisions.
std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
bool exact(double y) {
  const std::uint64_t exponent = (bits_of(y) >> 52) & 0x7ff;
  if (exponent == 0x7ff || y == 0.0) return true;  // inf, NaN, zero
  return y > -9e15 && y < 9e15 && y == static_cast<double>(static_cast<long long>(y));
}
// y moved by one ulp as the key decides; which function and which output is in the key.
double moved(double y, std::uint64_t key) {
  __atomic_fetch_add(&g_results, 1, __ATOMIC_RELAXED);
  if (exact(y)) return y;
  const std::uint64_t choice = mix(key ^ mix(g_seed)) % 3;
  if (choice == 0) return y;
  __atomic_fetch_add(&g_moved, 1, __ATOMIC_RELAXED);
  // One ulp away from zero (bits + 1) or towards it (bits - 1): both are neighbours.
  const std::uint64_t b = bits_of(y) + (choice == 1 ? 1 : -1);
  double out;
  std::memcpy(&out, &b, sizeof out);
  return out;
}

template <typename F>
F system_function(const char* name) {
  void* f = dlsym(RTLD_NEXT, name);
  if (f == nullptr) {
    std::fprintf(stderr, "other_libm: no %s after this library\n", name);
    std::abort();
  }
  return reinterpret_cast<F>(f);
}

using Unary = double (*)(double);
using Binary = double (*)(double, double);
using Lanes = __m128d (*)(__m128d);

double unary(Unary f, double x, std::uint64_t tag) { return moved(f(x), mix(bits_of(x)) ^ tag); }
double binary(Binary f, double x, double y, std::uint64_t tag) {
  return moved(f(x, y), mix(bits_of(x) ^ mix(bits_of(y))) ^ tag);
}
__m128d lanes(Lanes f, __m128d x, std::uint64_t tag) {
  double in[2], out[2];
  _mm_storeu_pd(in, x);
  _mm_storeu_pd(out, f(x));
  // A lane gets the decision its scalar function gets: libmvec and libm may differ, but by one rule.
  for (int i = 0; i < 2; ++i) out[i] = moved(out[i], mix(bits_of(in[i])) ^ tag);
  return _mm_loadu_pd(out);
}

// The system's functions, resolved once before any call (no lazy lookup
// for two threads to race on).
Unary g_sin, g_cos, g_atan, g_exp, g_log, g_log10, g_cbrt;
Binary g_atan2, g_pow, g_hypot;
Lanes g_sin2, g_cos2;
void (*g_sincos)(double, double*, double*);
long double (*g_powl)(long double, long double);
constexpr double kPi = 3.141592653589793;  // atan2's largest result

__attribute__((constructor)) void resolve() {
  if (const char* s = std::getenv("ROTOR_RUB_LIBM_SEED")) g_seed = std::strtoull(s, nullptr, 10);
  for (const auto& [f, name] : {std::pair<Unary*, const char*>{&g_sin, "sin"},
                                {&g_cos, "cos"},
                                {&g_atan, "atan"},
                                {&g_exp, "exp"},
                                {&g_log, "log"},
                                {&g_log10, "log10"},
                                {&g_cbrt, "cbrt"}}) {
    *f = system_function<Unary>(name);
  }
  for (const auto& [f, name] :
       {std::pair<Binary*, const char*>{&g_atan2, "atan2"}, {&g_pow, "pow"}, {&g_hypot, "hypot"}}) {
    *f = system_function<Binary>(name);
  }
  g_sin2 = system_function<Lanes>("_ZGVbN2v_sin");
  g_cos2 = system_function<Lanes>("_ZGVbN2v_cos");
  g_sincos = system_function<void (*)(double, double*, double*)>("sincos");
  g_powl = system_function<long double (*)(long double, long double)>("powl");
}

}  // namespace

extern "C" {
double sin(double x) { return unary(g_sin, x, 1); }
double cos(double x) { return unary(g_cos, x, 2); }
double atan(double x) { return unary(g_atan, x, 3); }
double exp(double x) { return unary(g_exp, x, 4); }
double log(double x) { return unary(g_log, x, 5); }
double log10(double x) { return unary(g_log10, x, 9); }
double cbrt(double x) { return unary(g_cbrt, x, 10); }
double atan2(double y, double x) {
  const double r = binary(g_atan2, y, x, 6);
  return r > kPi ? kPi : r < -kPi ? -kPi : r;
}
// An exact power (pow(x, 2), pow(2, -3)) stays exact, as in every libm.
double pow(double x, double y) {
  const double r = g_pow(x, y);
  if (static_cast<long double>(r) == g_powl(x, y)) return r;
  return binary(g_pow, x, y, 7);
}
double hypot(double x, double y) { return binary(g_hypot, x, y, 8); }
void sincos(double x, double* s, double* c) {
  g_sincos(x, s, c);
  *s = moved(*s, mix(bits_of(x)) ^ 1);
  *c = moved(*c, mix(bits_of(x)) ^ 2);
}
__m128d _ZGVbN2v_sin(__m128d x) { return lanes(g_sin2, x, 1); }
__m128d _ZGVbN2v_cos(__m128d x) { return lanes(g_cos2, x, 2); }
}
