// A patch's sampled limit surface (limit_surface.h) against what defines it: its support function's
// derivatives against finite differences, the size (the dual norm) against the largest ratio over
// 100,000 directions, the projection against the surface's own normals, the ball's answers to the
// bit, and the surface not depending on the order of the patch's points.
#include "core/contact/limit_surface.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

namespace igms {
namespace {

LimitSurface square() {
  const double u[4] = {0.1, -0.1, -0.1, 0.1}, v[4] = {0.1, 0.1, -0.1, -0.1};
  LimitSurface s;
  sampleLimitSurface(u, v, 4, s);
  return s;
}

LimitSurface triangle() {  // a foot's heel and two toes, from their centroid
  const double u[3] = {0.12, -0.04, -0.08}, v[3] = {0.0, 0.05, -0.05};
  LimitSurface s;
  sampleLimitSurface(u, v, 3, s);
  return s;
}

LimitSurface line() {
  const double u[2] = {-0.2, 0.2}, v[2] = {0.0, 0.0};
  LimitSurface s;
  sampleLimitSurface(u, v, 2, s);
  return s;
}

Vector3 randomVector(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Vector3(n(rng), n(rng), n(rng));
}

TEST(LimitSurface, SlidingAndSpinningAloneTakeTheLoadAndTheRadius) {
  for (const LimitSurface& s : {square(), triangle(), line()}) {
    ASSERT_GT(s.samples, 0);
    double total = 0.0;
    for (int k = 0; k < s.samples; ++k) total += s.weight[k];
    EXPECT_NEAR(total, 1.0 / std::sqrt(1.0 + kLimitSmoothing * kLimitSmoothing), 1e-15);
    EXPECT_NEAR(limitSupport(s, Vector3(0, 0, 1)), 1.0, 1e-14) << "pure spin: mu N r";
  }
  // A centred patch (the square, the line) slides with mu N whatever the direction.
  for (const LimitSurface& s : {square(), line()})
    for (double angle = 0.0; angle < 6.0; angle += 0.7) {
      const Vector3 w(std::cos(angle), std::sin(angle), 0.0);
      EXPECT_NEAR(limitSupport(s, w), 1.0, 1e-14);
      EXPECT_NEAR(limitSize(s, w), 1.0, 1e-12);
    }
  // And spins in place with mu N r: the square's and the line's spin is a wrench of size 1.
  for (const LimitSurface& s : {square(), line()}) EXPECT_NEAR(limitSize(s, Vector3(0, 0, 1)), 1.0, 1e-12);
}

TEST(LimitSurface, TheGradientAndHessianAreTheSupportFunctionsDerivatives) {
  std::mt19937 rng(7);
  const double e = 1e-6;
  for (const LimitSurface& s : {square(), triangle(), line()}) {
    double worst_g = 0.0, worst_h = 0.0;
    for (int trial = 0; trial < 200; ++trial) {
      const Vector3 w = randomVector(rng);
      Vector3 grad;
      Eigen::Matrix3d hess;
      const double h = limitDerivatives(s, w, grad, hess);
      EXPECT_DOUBLE_EQ(h, limitSupport(s, w));
      EXPECT_LT((grad - limitGradient(s, w)).norm(), 1e-15);
      EXPECT_NEAR(grad.dot(w), h, 1e-12 * h) << "h is homogeneous of degree one";
      for (int i = 0; i < 3; ++i) {
        const Vector3 d = Vector3::Unit(i) * e;
        worst_g = std::max(worst_g, std::abs((limitSupport(s, w + d) - limitSupport(s, w - d)) / (2 * e) - grad[i]));
        const Vector3 col = (limitGradient(s, w + d) - limitGradient(s, w - d)) / (2 * e);
        worst_h = std::max(worst_h, (col - hess.col(i)).cwiseAbs().maxCoeff() / (1.0 + hess.cwiseAbs().maxCoeff()));
      }
    }
    std::printf("%d samples: gradient against differences %.1e, Hessian %.1e\n", s.samples, worst_g, worst_h);
    EXPECT_LT(worst_g, 1e-8);
    EXPECT_LT(worst_h, 1e-5);
  }
}

TEST(LimitSurface, ASizeIsTheLargestRatioOverEveryDirection) {
  std::mt19937 rng(11);
  for (const LimitSurface& s : {square(), triangle(), line()}) {
    for (int trial = 0; trial < 10; ++trial) {
      const Vector3 f = randomVector(rng);
      const double size = limitSize(s, f);
      double largest = 0.0;
      for (int k = 0; k < 100000; ++k) {
        const Vector3 x = randomVector(rng);
        const double ratio = f.dot(x) / limitSupport(s, x);
        EXPECT_LE(ratio, size * (1.0 + 1e-12)) << "f / size is inside the surface";
        largest = std::max(largest, ratio);
      }
      EXPECT_GT(largest, size * (1.0 - 2e-3)) << "and on it: a direction nearly reaches it";
    }
  }
}

TEST(LimitSurface, AProjectionLandsOnTheSurfaceWhereItsNormalPointsBackAtTheWrench) {
  std::mt19937 rng(13);
  for (const LimitSurface& s : {square(), triangle(), line()}) {
    for (int trial = 0; trial < 200; ++trial) {
      const Vector3 f = randomVector(rng);
      for (const double share : {0.999, 0.9, 0.5, 0.1, 1e-3}) {  // just outside to far outside
        const double cap = share * limitSize(s, f);
        const Vector3 q = limitProject(s, f, cap);
        EXPECT_NEAR(limitSize(s, q), cap, 1e-10 * cap) << share;
        // The nearest point q has f - q as its outward normal, so the surface's point for that normal
        // is q itself.
        EXPECT_LT((cap * limitGradient(s, f - q) - q).norm(), 1e-9 * cap) << share;
      }
      const Vector3 inside = f * 0.999 / limitSize(s, f);
      EXPECT_EQ(limitProject(s, inside, 1.0), inside) << "inside: unchanged";
    }
  }
}

TEST(LimitSurface, TheBoundsHoldInEveryDirectionAndAreNearlyReached) {
  std::mt19937 rng(23);
  for (const LimitSurface& s : {square(), triangle(), line()}) {
    double least = 1e300, most = 0.0;
    for (int k = 0; k < 100000; ++k) {
      const Vector3 x = randomVector(rng);
      const double h = limitSupport(s, x) / x.norm();  // the surface's distance along x's normal
      EXPECT_GE(h, s.inner * (1.0 - 1e-12)) << "the inner ball is inside the surface";
      EXPECT_LE(h, s.outer * (1.0 + 1e-12)) << "the surface is inside the outer ball";
      least = std::min(least, h);
      most = std::max(most, h);
    }
    std::printf("%d samples: inner bound %.4f, least %.4f; most %.4f, outer bound %.4f\n", s.samples, s.inner, least,
                most, s.outer);
    EXPECT_GT(s.inner, 0.5 * least) << "the inner bound is not far from the surface";
    EXPECT_LT(s.outer, 1.15 * most) << "the outer is near it";
  }
}

// A hint (the normal of a last solve) only starts Newton's method: right, near, random or opposite,
// the answers are those without one, and the hint comes back as the answer's normal.
TEST(LimitSurface, AHintChangesNothingButWhereNewtonStarts) {
  std::mt19937 rng(29);
  for (const LimitSurface& s : {square(), triangle(), line()}) {
    for (int trial = 0; trial < 100; ++trial) {
      const Vector3 f = randomVector(rng);
      const double size = limitSize(s, f);
      for (const double share : {1.01, 0.999, 0.9, 0.5, 0.1, 1e-3}) {  // just inside to far outside
        const double cap = share * size;
        const Vector3 plain = limitProject(s, f, cap);
        Vector3 right = Vector3::Zero();
        limitProject(s, f, cap, &right);
        Vector3 near = right + 0.05 * right.norm() * randomVector(rng);
        for (Vector3 hint : {right, near, randomVector(rng), Vector3(-right)}) {
          if (share > 1.0) hint = randomVector(rng);  // inside: the projection leaves it alone
          const Vector3 given = hint;
          EXPECT_LT((limitProject(s, f, cap, &hint) - plain).norm(), 1e-12 * cap) << share;
          if (share < 1.0)
            EXPECT_LT((cap * limitGradient(s, hint) - plain).norm(), 1e-9 * cap) << "the answer's normal";
          for (const double margin : {0.99, 1.01}) {
            Vector3 again = given;
            EXPECT_EQ(limitInside(s, f, margin * size, &again), limitInside(s, f, margin * size)) << margin;
          }
        }
      }
    }
  }
}

TEST(LimitSurface, WithoutSamplesItIsTheBallToTheBit) {
  const LimitSurface ball;
  std::mt19937 rng(17);
  for (int trial = 0; trial < 100; ++trial) {
    const Vector3 f = randomVector(rng);
    EXPECT_EQ(limitSize(ball, f), f.norm());
    EXPECT_EQ(limitSupport(ball, f), f.norm());
    const double cap = 0.5 * f.norm();
    EXPECT_EQ(limitProject(ball, f, cap), f * (cap / f.norm()));
  }
  LimitSurface one;
  const double u = 0.0, v = 0.0;
  sampleLimitSurface(&u, &v, 1, one);
  EXPECT_EQ(one.samples, 0) << "one point: no patch";
}

TEST(LimitSurface, ThePointsOrderDoesNotMatter) {
  const double u[4] = {0.1, -0.1, -0.1, 0.1}, v[4] = {0.15, 0.1, -0.1, -0.12};
  const int orders[3][4] = {{0, 1, 2, 3}, {2, 0, 3, 1}, {3, 2, 1, 0}};
  LimitSurface first;
  std::mt19937 rng(19);
  for (int o = 0; o < 3; ++o) {
    double uu[4], vv[4];
    for (int k = 0; k < 4; ++k) uu[k] = u[orders[o][k]], vv[k] = v[orders[o][k]];
    LimitSurface s;
    sampleLimitSurface(uu, vv, 4, s);
    if (o == 0) first = s;
    for (int trial = 0; trial < 20; ++trial) {
      const Vector3 w = randomVector(rng);
      EXPECT_NEAR(limitSupport(s, w), limitSupport(first, w), 1e-14 * w.norm());
    }
  }
}

}  // namespace
}  // namespace igms
