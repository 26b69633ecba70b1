// A patch's torsion radius (the mean distance from its centroid over its polygon) against the same
// integral taken numerically: the polygon cut into triangles at the centroid, each edge's integral
// of |r| along the edge (the edge at distance d, s along it: d sqrt(d^2 + s^2) / 3 per unit s) by
// composite Simpson in t = asinh(s / d); plus the square's closed form, a line's quarter length,
// and the order of the points not mattering.
#include "core/contact/patch_radius.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

namespace {

struct Polygon {
  std::vector<double> u, v;  // from the points' mean, as the contact frame passes them
};

Polygon centred(std::vector<double> u, std::vector<double> v) {
  double mu = 0.0, mv = 0.0;
  for (size_t k = 0; k < u.size(); ++k) mu += u[k], mv += v[k];
  mu /= static_cast<double>(u.size());
  mv /= static_cast<double>(v.size());
  for (size_t k = 0; k < u.size(); ++k) u[k] -= mu, v[k] -= mv;
  return {u, v};
}

double radius(const Polygon& p) { return igms::patchTorsionRadius(p.u.data(), p.v.data(), static_cast<int>(p.u.size())); }

// The mean of |r| over the convex polygon (the origin inside), its corners sorted by atan2.
double numericMean(const Polygon& p) {
  const size_t n = p.u.size();
  std::vector<size_t> order(n);
  for (size_t k = 0; k < n; ++k) order[k] = k;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return std::atan2(p.v[a], p.u[a]) < std::atan2(p.v[b], p.u[b]); });
  double moment = 0.0, area = 0.0;
  for (size_t k = 0; k < n; ++k) {
    const size_t a = order[k], b = order[(k + 1) % n];
    const double ex = p.u[b] - p.u[a], ey = p.v[b] - p.v[a], len = std::sqrt(ex * ex + ey * ey);
    const double d = std::abs(p.u[a] * ey - p.v[a] * ex) / len;
    const double sa = (p.u[a] * ex + p.v[a] * ey) / len, sb = (p.u[b] * ex + p.v[b] * ey) / len;
    if (!(d > 0.0)) continue;  // an edge through the origin: an empty triangle
    // s = d sinh(t): the integrand d sqrt(d^2 + s^2) / 3 ds becomes d^3 cosh^2(t) / 3 dt, smooth
    // however near the origin the edge passes
    const int m = 20000;  // Simpson panels
    const double ta = std::asinh(sa / d), h = (std::asinh(sb / d) - ta) / m;
    double sum = 0.0;
    for (int i = 0; i <= m; ++i) {
      const double c = std::cosh(ta + i * h);
      sum += ((i == 0 || i == m) ? 1.0 : (i % 2 ? 4.0 : 2.0)) * d * d * d * c * c / 3.0;
    }
    moment += sum * h / 3.0;
    area += 0.5 * d * (sb - sa);
  }
  return moment / area;
}

TEST(PatchRadius, ASquareTakesItsClosedForm) {
  const double a = 0.2;  // the mean distance from a square's centre: a (sqrt 2 + ln(1 + sqrt 2)) / 6
  const Polygon p = centred({a / 2, -a / 2, -a / 2, a / 2}, {a / 2, a / 2, -a / 2, -a / 2});
  const double exact = a * (std::sqrt(2.0) + std::log(1.0 + std::sqrt(2.0))) / 6.0;
  EXPECT_NEAR(radius(p), exact, 1e-15);
  EXPECT_NEAR(numericMean(p), exact, 1e-13) << "the reference itself";
}

TEST(PatchRadius, PolygonsMatchTheNumericIntegralInAnyOrder) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> size(0.005, 0.5), turn(-M_PI, M_PI);
  double worst = 0.0;
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<double> u, v;
    const double ra = size(rng), t0 = turn(rng);
    // every third a rectangle (down to 1:100), else a triangle or a quadrilateral with its corners
    // on an ellipse at increasing angles (convex)
    const double rb = trial % 3 == 0 ? ra * (trial % 2 ? size(rng) / 0.5 : 0.01 * (1 + trial % 7)) : size(rng);
    std::vector<double> t;
    if (trial % 3 == 0) {
      t = {0.25 * M_PI, 0.75 * M_PI, 1.25 * M_PI, 1.75 * M_PI};
    } else {
      t.resize(trial % 3 == 1 ? 3 : 4);
      for (double& x : t) x = turn(rng);
      std::sort(t.begin(), t.end());
    }
    for (double tk : t) {
      const double x = ra * (trial % 3 == 0 ? (std::cos(tk) > 0 ? 1 : -1) : std::cos(tk));
      const double y = rb * (trial % 3 == 0 ? (std::sin(tk) > 0 ? 1 : -1) : std::sin(tk));
      u.push_back(x * std::cos(t0) - y * std::sin(t0) + 0.3);  // off the origin: centred() moves it
      v.push_back(x * std::sin(t0) + y * std::cos(t0) - 0.1);
    }
    const Polygon p = centred(u, v);
    const double truth = numericMean(p);
    Polygon shuffled;  // the same points in another order
    std::vector<size_t> perm(p.u.size());
    for (size_t k = 0; k < perm.size(); ++k) perm[k] = k;
    std::shuffle(perm.begin(), perm.end(), rng);
    for (size_t k : perm) shuffled.u.push_back(p.u[k]), shuffled.v.push_back(p.v[k]);
    const double got = radius(shuffled);
    EXPECT_NEAR(got, truth, 1e-12 * truth) << "trial " << trial;
    EXPECT_NEAR(got, radius(p), 1e-14 * truth) << "trial " << trial << ": the order changed it";
    worst = std::max(worst, std::abs(got - truth) / truth);
  }
  std::printf("300 polygons: worst relative difference %.1e from the numeric integral\n", worst);
}

TEST(PatchRadius, ALineTakesAQuarterOfItsLength) {
  EXPECT_DOUBLE_EQ(radius(centred({0.0, 0.3}, {0.0, 0.4})), 0.125);  // 0.5 long
  // four points in a row (a cylinder's rim ends and two between), in no order
  EXPECT_DOUBLE_EQ(radius(centred({0.2, -0.1, 0.1, 0.0}, {0.0, 0.0, 0.0, 0.0})), 0.25 * 0.3);
  const double at_u = 0.0, at_v = 0.0;
  EXPECT_EQ(igms::patchTorsionRadius(&at_u, &at_v, 1), 0.0);
}

TEST(PatchRadius, AThinStripIsAPolygonDownToItsFloor) {
  // 2 m by 4 um: area 8e-6 m^2 against the floor 1e-6 x chord^2 (4e-6), so still a polygon. Its mean
  // distance from the centre is 0.5 + 9.77e-12 (the rectangle's Cartesian closed form,
  // [2ABD + A^3 ln((B + D) / A) + B^3 ln((A + D) / B)] / 6AB with half sides A, B and D = |(A, B)|,
  // in 50-digit decimal arithmetic); a log of (rho_b + s_b) / (rho_a + s_a) loses that 1e-11 to
  // cancellation (it gave 0.5 + 6.9e-12).
  const Polygon p = centred({-1.0, 1.0, 1.0, -1.0}, {-2e-6, -2e-6, 2e-6, 2e-6});
  EXPECT_NEAR(radius(p), 0.50000000000976589593, 4e-16);
  EXPECT_NEAR(numericMean(p), 0.50000000000976589593, 1e-13) << "the reference itself";
  // half as wide: under the floor, a line
  EXPECT_DOUBLE_EQ(radius(centred({-1.0, 1.0, 1.0, -1.0}, {-1e-6, -1e-6, 1e-6, 1e-6})), 0.25 * std::sqrt(4.0 + 4e-12));
}

}  // namespace
