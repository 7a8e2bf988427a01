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

namespace neurov {
namespace detail {

// Inlined so that the three angles' polynomials overlap in the pipeline.
#if defined(__GNUC__) || defined(__clang__)
__attribute__((always_inline))
#endif
inline void sincos(double x, double& s, double& c) noexcept {
  const double ax = std::fabs(x);
  if (!(ax <= 1024.0)) {  // also NaN
    s = std::sin(x);
    c = std::cos(x);
    return;
  }
  if (ax < 0x1p-27) {  // sin x = x and cos x = 1 to the last bit (keeps -0)
    s = x;
    c = 1.0;
    return;
  }
  // n = nearest integer to x / (pi/2): adding 1.5 * 2^52 rounds it into the
  // low bits of t.
  const double shifter = 0x1.8p52;
  const double t = x * 6.36619772367581382433e-01 + shifter;
  const double n = t - shifter;
  // pi/2 = p1 + p2 + p3 + p4, p1..p3 of 33 bits, so n * p1..p3 are exact for
  // |n| < 2^20 and r keeps its accuracy next to multiples of pi/2.
  const double r = (((x - n * 1.57079632673412561417e+00) - n * 6.07710050630396597660e-11) -
                    n * 2.02226624871116645580e-21) -
                   n * 8.47842766036889956997e-32;
  const double z = r * r, w = z * z;
  // fdlibm __kernel_sin and __kernel_cos on |r| <= pi/4.
  const double ps = 8.33333333332248946124e-03 +
                    z * (-1.98412698298579493134e-04 + z * 2.75573137070700676789e-06) +
                    z * w * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10);
  const double sr = r + z * r * (-1.66666666666666324348e-01 + z * ps);
  const double pc =
      z * (4.16666666666666019037e-02 +
           z * (-1.38888888888741095749e-03 + z * 2.48015872894767294178e-05)) +
      w * w *
          (-2.75573143513906633035e-07 +
           z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11));
  const double hz = 0.5 * z;
  const double one_minus = 1.0 - hz;
  const double cr = one_minus + (((1.0 - one_minus) - hz) + z * pc);
  std::uint64_t bits;
  std::memcpy(&bits, &t, sizeof bits);
  const unsigned q = static_cast<unsigned>(bits) & 3u;  // quadrant: n mod 4
  const double a = (q & 1u) ? cr : sr, b = (q & 1u) ? -sr : cr;
  s = (q & 2u) ? -a : a;
  c = (q & 2u) ? -b : b;
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
