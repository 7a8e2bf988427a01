// sin and cos of one angle together, for the Euler-angle trigonometry that
// every plant evaluation and controller step starts with (three angles; the
// library's sincos was a third of a closed-loop run).
//
// Double: Cody-Waite reduction by pi/2 in four parts and fdlibm's kernel
// polynomials, within 2 ulp of the true value for |x| <= 1024 (the
// library's own sin/cos outside that, and for float on targets without
// hardware double, where firmware keeps what it had).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "neurov/core/config.hpp"
#include "neurov/core/lane_math.hpp"

namespace neurov {
namespace detail {

/// sin and cos of each lane of V (double lanes; core/lane_math.hpp), the
/// same operations for one lane as for many, so a batch of runs in SIMD
/// lanes gets each run's sines bit for bit.
template <typename V>
NEUROV_ALWAYS_INLINE void sincos_lanes(const V& x, V& s, V& c) noexcept {
  static_assert(std::is_same_v<LaneScalar<V>, double>, "double lanes");
  V ax;
  lane_abs(x, ax);
  const auto out_of_range = (ax <= V{} + 1024.0) == 0;  // also NaN
  const auto tiny = ax < V{} + 0x1p-27;
  const V xr = out_of_range ? V{} : x;
  // n = nearest integer to x / (pi/2): adding 1.5 * 2^52 rounds it into the
  // low bits of t.
  const V shifter = V{} + 0x1.8p52;
  const V t = xr * 6.36619772367581382433e-01 + shifter;
  const V n = t - shifter;
  // pi/2 = p1 + p2 + p3 + p4, p1..p3 of 33 bits, so n * p1..p3 are exact for
  // |n| < 2^20 and r keeps its accuracy next to multiples of pi/2.
  const V r = (((xr - n * 1.57079632673412561417e+00) - n * 6.07710050630396597660e-11) -
               n * 2.02226624871116645580e-21) -
              n * 8.47842766036889956997e-32;
  const V z = r * r, w = z * z;
  // fdlibm __kernel_sin and __kernel_cos on |r| <= pi/4.
  const V ps = 8.33333333332248946124e-03 +
               z * (-1.98412698298579493134e-04 + z * 2.75573137070700676789e-06) +
               z * w * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10);
  const V sr = r + z * r * (-1.66666666666666324348e-01 + z * ps);
  const V pc = z * (4.16666666666666019037e-02 +
                    z * (-1.38888888888741095749e-03 + z * 2.48015872894767294178e-05)) +
               w * w *
                   (-2.75573143513906633035e-07 +
                    z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11));
  const V hz = 0.5 * z;
  const V one_minus = 1.0 - hz;
  const V cr = one_minus + (((1.0 - one_minus) - hz) + z * pc);
  BitsOf<V> q;  // quadrant: n mod 4 in the low bits of t
  bits_of(t, q);
  const auto odd = (q & 1u) != 0u, upper = (q & 2u) != 0u;
  const V a = odd ? cr : sr, b = odd ? -sr : cr;
  // sin x = x and cos x = 1 to the last bit for tiny x (keeps -0).
  s = tiny ? x : (upper ? -a : a);
  c = tiny ? V{} + 1.0 : (upper ? -b : b);
  if (any(out_of_range)) {  // the library's own outside |x| <= 1024
    for (int i = 0; i < kLanes<V>; ++i) {
      if (!mask_lane(out_of_range, i)) continue;
      set_lane(s, i, std::sin(lane(x, i)));
      set_lane(c, i, std::cos(lane(x, i)));
    }
  }
}

// Inlined so that the three angles' polynomials overlap in the pipeline.
NEUROV_ALWAYS_INLINE void sincos(double x, double& s, double& c) noexcept {
  sincos_lanes(x, s, c);
}

inline void sincos(float x, float& s, float& c) noexcept {
#if defined(__x86_64__) || defined(__aarch64__) || defined(_M_X64) || defined(_M_ARM64)
  // Hardware double: the double routine rounded to float (within 0.5 ulp
  // plus a rounding).
  double sd, cd;
  sincos(static_cast<double>(x), sd, cd);
  s = static_cast<float>(sd);
  c = static_cast<float>(cd);
#else
  s = std::sin(x);
  c = std::cos(x);
#endif
}

/// Any other scalar type: the library's functions.
template <typename Scalar>
inline void sincos(Scalar x, Scalar& s, Scalar& c) noexcept {
  using std::cos;
  using std::sin;
  s = sin(x);
  c = cos(x);
}

}  // namespace detail
}  // namespace neurov
