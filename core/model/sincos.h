// sin and cos of a joint angle together, inlined: reduce by pi/2 (Cody-Waite,
// pi/2 split in three parts so n * part is exact), then the minimax kernels of
// fdlibm on [-pi/4, pi/4] (error below 2^-58 there) and the quadrant's swap and
// signs, the reduction's rounding carried into the kernels as a tail (as
// fdlibm does). Within 0.9 ulp of the exact value for |x| < 1e5 rad
// (tests/unit/sincos_test.cc measures it against long double); outside that
// range, or for a non-finite angle, it is libm's.
//
// Why not libm: every kernel places each joint with one sincos, and glibc's
// out-of-line call (with its argument checks and its slow path for huge
// arguments) was a fifth of the PUMA's CRBA; this takes about 2/3 of its time in
// a loop and, inlined, overlaps with the placement around it.
#pragma once

#include <cmath>
#include <cstdint>

namespace igms {

namespace detail {
// |sin x - x (1 + x^2 P(x^2))| < 2^-58 and |cos x - (1 - x^2/2 + x^4 Q(x^2))| < 2^-58 on [-pi/4, pi/4].
constexpr double kS1 = -1.66666666666666324348e-01, kS2 = 8.33333333332248946124e-03,
                 kS3 = -1.98412698298579493134e-04, kS4 = 2.75573137070700676789e-06,
                 kS5 = -2.50507602534068634195e-08, kS6 = 1.58969099521155010221e-10;
constexpr double kC1 = 4.16666666666666019037e-02, kC2 = -1.38888888888741095749e-03,
                 kC3 = 2.48015872894767294178e-05, kC4 = -2.75573143513906633035e-07,
                 kC5 = 2.08757232129817482790e-09, kC6 = -1.13596475577881948265e-11;
// pi/2 = kPio2A + kPio2B + kPio2C, the first two with 33 significant bits: n * kPio2A and
// n * kPio2B are exact for |n| < 2^20.
constexpr double kPio2A = 1.57079632673412561417e+00, kPio2B = 6.07710050630396597660e-11,
                 kPio2C = 2.02226624879595063154e-21;
constexpr double kTwoOverPi = 6.36619772367581382433e-01;

// sin(x + y) and cos(x + y) for |x| <= pi/4 and y the tail of the reduced argument (|y| < ulp(x)).
inline double sinKernel(double x, double y) {
  const double z = x * x, v = z * x;
  const double r = kS2 + z * (kS3 + z * (kS4 + z * (kS5 + z * kS6)));
  return x - ((z * (0.5 * y - v * r) - y) - v * kS1);
}

inline double cosKernel(double x, double y) {
  const double z = x * x;
  const double r = z * (kC1 + z * (kC2 + z * (kC3 + z * (kC4 + z * (kC5 + z * kC6)))));
  // 1 - z/2 rounded, then what the rounding lost, so the sum keeps its last bit.
  const double hz = 0.5 * z, w = 1.0 - hz;
  return w + (((1.0 - w) - hz) + (z * r - x * y));
}
}  // namespace detail

inline void sinCos(double x, double& s, double& c) {
  constexpr double kLimit = 1e5;  // |n| < 2^16: n * kPio2A and n * kPio2B exact
  if (!(std::fabs(x) < kLimit)) {  // also NaN and infinities
    s = std::sin(x);
    c = std::cos(x);
    return;
  }
  // Round to the nearest integer without a libm call (roundsd needs SSE4.1): adding 1.5 * 2^52
  // leaves no fraction bits, and the default rounding mode rounds to nearest.
  constexpr double kShifter = 6755399441055744.0;
  const double n = (x * detail::kTwoOverPi + kShifter) - kShifter;
  // r = hi + lo: x - n kPio2A is exact, the rounding of the next subtraction is kept in lo.
  const double t = x - n * detail::kPio2A, w = n * detail::kPio2B;
  const double hi = t - w, lo = ((t - hi) - w) - n * detail::kPio2C;
  const double sr = detail::sinKernel(hi, lo), cr = detail::cosKernel(hi, lo);
  const auto quadrant = static_cast<std::int64_t>(n) & 3;
  // x = n pi/2 + r: quadrant 0 (sin r, cos r), 1 (cos r, -sin r), 2 (-sin r, -cos r), 3 (-cos r, sin r).
  const double s0 = (quadrant & 1) ? cr : sr, c0 = (quadrant & 1) ? sr : cr;
  s = (quadrant & 2) ? -s0 : s0;
  c = ((quadrant + 1) & 2) ? -c0 : c0;
}

}  // namespace igms
