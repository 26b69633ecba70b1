#include "core/contact/patch_radius.h"

#include <algorithm>
#include <cmath>

namespace igms {

namespace {

constexpr int kMaxPoints = 4;
constexpr double kLineArea = 1e-6;  // an area below this times the longest chord squared: a line

// A point's angle about the origin as a cheaper number in the same order: atan2's (-pi, pi] mapped
// monotonically onto (-2, 2] along the diamond |x| + |y| = 1.
double pseudoAngle(double x, double y) {
  const double s = std::abs(x) + std::abs(y);
  if (!(s > 0.0)) return 0.0;  // the centroid itself (atan2(0, 0) is 0 too)
  const double t = y / s;
  return x >= 0.0 ? t : (y >= 0.0 ? 2.0 - t : -2.0 - t);
}

// The integral of |r| over the triangle (origin, a, b), with d the origin's distance to the line ab,
// s the signed position along it from the foot and len = s_b - s_a: [d s rho + d^3 asinh(s / d)] / 6
// between the ends (rho = sqrt(d^2 + s^2)). Both differences are taken in forms that do not cancel:
// with the ends on opposite sides of the foot their terms add; on one side, s_b rho_b - s_a rho_a =
// len (s_a + s_b)(d^2 + s_a^2 + s_b^2) / (s_b rho_b + s_a rho_a), and asinh's difference is one
// asinh, of (s_b rho_a - s_a rho_b) / d^2 = len (s_a + s_b) / (s_b rho_a + s_a rho_b).
double triangleMoment(double d, double sa, double sb, double len) {
  const double ra = std::sqrt(d * d + sa * sa), rb = std::sqrt(d * d + sb * sb);
  const bool one_side = sa * sb > 0.0;
  const double products = one_side ? len * (sa + sb) * (d * d + sa * sa + sb * sb) / (sb * rb + sa * ra) : sb * rb - sa * ra;
  double m = d * products;
  if (d * d * d > 0.0)  // below ~1e-108 m the term is nothing, and d^2 would underflow
    m += d * d * d * std::asinh(one_side ? len * (sa + sb) / (sb * ra + sa * rb) : (sb * ra - sa * rb) / (d * d));
  return std::abs(m) / 6.0;
}

// The longest chord's length squared, and its ends (where asked).
double longestChord(const double* u, const double* v, int n, int* end_a, int* end_b) {
  double extent2 = 0.0;
  for (int a = 0; a < n; ++a)
    for (int b = a + 1; b < n; ++b) {
      const double d2 = (u[a] - u[b]) * (u[a] - u[b]) + (v[a] - v[b]) * (v[a] - v[b]);
      if (d2 > extent2 || (a == 0 && b == 1)) {
        extent2 = d2;
        if (end_a) *end_a = a;
        if (end_b) *end_b = b;
      }
    }
  return extent2;
}

}  // namespace

// Every patch, every step: one asinh an edge and no atan2 or hypot (the few dozen such calls a step
// took were a tenth of a small scene's step).
double patchTorsionRadius(const double* u, const double* v, int n) {
  n = std::min(n, kMaxPoints);
  if (n < 2) return 0.0;
  int order[kMaxPoints];
  patchOrder(u, v, n, order);
  double area = 0.0, moment = 0.0;  // the polygon's area and the integral of |r| over it
  for (int k = 0; n > 2 && k < n; ++k) {
    const int a = order[k], b = order[(k + 1) % n];
    const double ex = u[b] - u[a], ey = v[b] - v[a], len = std::sqrt(ex * ex + ey * ey);
    if (!(len > 0.0)) continue;
    const double d = std::abs(u[a] * ey - v[a] * ex) / len;
    const double sa = (u[a] * ex + v[a] * ey) / len, sb = (u[b] * ex + v[b] * ey) / len;
    area += 0.5 * d * std::abs(sb - sa);
    moment += triangleMoment(d, sa, sb, len);
  }
  const double extent2 = longestChord(u, v, n, nullptr, nullptr);
  if (!(area > kLineArea * extent2)) return 0.25 * std::sqrt(extent2);  // a line, or all but one
  return moment / area;
}

void patchOrder(const double* u, const double* v, int n, int* order) {
  n = std::min(n, kMaxPoints);
  double angle[kMaxPoints];
  for (int k = 0; k < n; ++k) {  // around the origin by angle, insertion sort: a handful of points
    angle[k] = pseudoAngle(u[k], v[k]);
    int j = k;
    for (; j > 0 && angle[order[j - 1]] > angle[k]; --j) order[j] = order[j - 1];
    order[j] = k;
  }
}

bool patchHasArea(const double* u, const double* v, int n, const int* order, int* a, int* b) {
  n = std::min(n, kMaxPoints);
  const double extent2 = longestChord(u, v, n, a, b);
  double twice = 0.0;  // the polygon's area, twice (shoelace, in order)
  for (int k = 0; n > 2 && k < n; ++k) {
    const int p = order[k], q = order[(k + 1) % n];
    twice += u[p] * v[q] - u[q] * v[p];
  }
  return 0.5 * std::abs(twice) > kLineArea * extent2;
}

}  // namespace igms
