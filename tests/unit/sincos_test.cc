// sinCos against long double sin and cos: within 0.9 ulp over joint-angle
// ranges and up to its 1e5 rad limit, exact signs and quadrants around every
// multiple of pi/2, and libm's answer beyond the limit and for non-finite input.
#include "core/model/sincos.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace {

// |got - exact| in units of the last place of the double nearest to exact.
double ulps(long double exact, double got) {
  const double e = static_cast<double>(exact);
  const double ulp = std::fabs(e) < std::numeric_limits<double>::min()
                         ? std::numeric_limits<double>::denorm_min()
                         : std::nextafter(std::fabs(e), INFINITY) - std::fabs(e);
  return static_cast<double>(std::fabs(static_cast<long double>(got) - exact) / ulp);
}

double worstOver(double range, int n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-range, range);
  double worst = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = u(rng);
    double s, c;
    igms::sinCos(x, s, c);
    worst = std::max({worst, ulps(sinl(x), s), ulps(cosl(x), c)});
  }
  return worst;
}

TEST(SinCos, WithinPointNineUlpOverJointRangesAndUpToItsLimit) {
  std::mt19937_64 rng(7);
  for (double range : {0.785, 3.2, 10.0, 100.0, 1e4, 99999.0}) {
    const double worst = worstOver(range, 200000, rng);
    EXPECT_LT(worst, 0.9) << "|x| < " << range;
  }
}

TEST(SinCos, NeighboursOfEveryQuarterTurn) {
  double worst = 0.0;
  for (int k = -4000; k <= 4000; ++k) {
    double x = k * (M_PI / 2);
    for (int step = 0; step < 3; ++step) x = std::nextafter(x, -INFINITY);
    for (int step = 0; step < 7; ++step, x = std::nextafter(x, INFINITY)) {
      double s, c;
      igms::sinCos(x, s, c);
      worst = std::max({worst, ulps(sinl(x), s), ulps(cosl(x), c)});
    }
  }
  EXPECT_LT(worst, 0.9);
}

TEST(SinCos, SignedZeroLargeAndNonFinite) {
  double s, c;
  igms::sinCos(-0.0, s, c);
  EXPECT_TRUE(std::signbit(s));
  EXPECT_EQ(c, 1.0);
  for (double x : {1e5, -2.5e5, 1e300}) {
    igms::sinCos(x, s, c);
    EXPECT_EQ(s, std::sin(x)) << x;
    EXPECT_EQ(c, std::cos(x)) << x;
  }
  igms::sinCos(INFINITY, s, c);
  EXPECT_TRUE(std::isnan(s) && std::isnan(c));
  igms::sinCos(NAN, s, c);
  EXPECT_TRUE(std::isnan(s) && std::isnan(c));
}

}  // namespace
