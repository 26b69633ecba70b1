// Lemke's method (core/contact/lemke.h) against the LCP's own conditions and a brute-force search over
// its 2^n complementary bases, on problems principal pivoting needs (P-matrices) and problems it does
// not reach (Stewart and Trinkle's friction LCP, copositive-plus, not a P-matrix).
#include "core/contact/lemke.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace igms {
namespace {

// max over rows of the conditions' violation: z < 0, w < 0, min(z, w) > 0.
double violation(const MatrixX& M, const VectorX& q, const VectorX& z) {
  const VectorX w = M * z + q;
  double worst = 0.0;
  for (int i = 0; i < q.size(); ++i)
    worst = std::max({worst, -z[i], -w[i], std::min(z[i], w[i])});
  return worst;
}

// Every complementary basis: the answers that meet the conditions (a P-matrix has exactly one).
std::vector<VectorX> bruteForce(const MatrixX& M, const VectorX& q) {
  const int n = static_cast<int>(q.size());
  std::vector<VectorX> found;
  for (int mask = 0; mask < (1 << n); ++mask) {
    std::vector<int> in;
    for (int i = 0; i < n; ++i)
      if (mask & (1 << i)) in.push_back(i);
    VectorX z = VectorX::Zero(n);
    if (!in.empty()) {
      MatrixX A(in.size(), in.size());
      VectorX b(in.size());
      for (size_t r = 0; r < in.size(); ++r) {
        for (size_t c = 0; c < in.size(); ++c) A(r, c) = M(in[r], in[c]);
        b[r] = -q[in[r]];
      }
      const VectorX x = A.fullPivLu().solve(b);
      for (size_t r = 0; r < in.size(); ++r) z[in[r]] = x[r];
    }
    if (violation(M, q, z) < 1e-9) found.push_back(z);
  }
  return found;
}

TEST(Lemke, SolvesRandomPMatricesAsTheOnlyAnswer) {
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  Lemke lemke(12);
  int nontrivial = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + trial % 8;
    MatrixX A(n, n), S(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        A(i, j) = normal(rng);
        S(i, j) = normal(rng);
      }
    // Positive definite plus skew-symmetric: a P-matrix, not symmetric.
    const MatrixX M = A * A.transpose() + 0.1 * MatrixX::Identity(n, n) + (S - S.transpose());
    VectorX q(n);
    for (int i = 0; i < n; ++i) q[i] = normal(rng);
    VectorX z(n);
    ASSERT_TRUE(lemke.solve(M, q, n, z)) << "trial " << trial;
    const std::vector<VectorX> all = bruteForce(M, q);
    ASSERT_EQ(all.size(), 1u) << "trial " << trial;
    EXPECT_LE((z - all[0]).cwiseAbs().maxCoeff(), 1e-9) << "trial " << trial;
    EXPECT_LE(violation(M, q, z), 1e-12) << "trial " << trial;
    nontrivial += z.cwiseAbs().maxCoeff() > 0.0 && q.minCoeff() < 0.0;
  }
  EXPECT_GT(nontrivial, 150);
}

// Stewart and Trinkle's LCP of a unit mass on a floor (one point, d generators around the tangent
// plane): pushed sideways by impulse p with gravity's g h, mu = 0.5. Below mu g h it sticks; above, it
// slides with friction mu g h against the push and speed p - mu g h. M is copositive-plus, not a
// P-matrix (its slip-speed row has a zero diagonal).
TEST(Lemke, SolvesTheLinearisedConeOfABlockPushedOnAFloor) {
  const int d = 8;
  const int n = 1 + d + 1;
  const double mu = 0.5, gh = 9.81e-3;
  std::vector<Eigen::Vector2d> dirs;
  for (int j = 0; j < d; ++j) dirs.emplace_back(std::cos(2 * M_PI * j / d), std::sin(2 * M_PI * j / d));
  Lemke lemke(n);
  for (const double p : {0.2 * mu * gh, 0.9 * mu * gh, 1.5 * mu * gh, 4.0 * mu * gh}) {
    // u = b + W lambda with W = I (unit mass, a point: normal and tangents decoupled), b = (-g h, p, 0).
    MatrixX M = MatrixX::Zero(n, n);
    VectorX q = VectorX::Zero(n);
    M(0, 0) = 1.0;
    q[0] = -gh;
    for (int i = 0; i < d; ++i) {
      for (int j = 0; j < d; ++j) M(1 + i, 1 + j) = dirs[i].dot(dirs[j]);
      M(1 + i, n - 1) = 1.0;
      M(n - 1, 1 + i) = -1.0;
      q[1 + i] = dirs[i].dot(Eigen::Vector2d(p, 0.0));
    }
    M(n - 1, 0) = mu;
    VectorX z(n);
    ASSERT_TRUE(lemke.solve(M, q, n, z)) << p;
    EXPECT_LE(violation(M, q, z), 1e-12) << p;
    Eigen::Vector2d f = Eigen::Vector2d::Zero();
    for (int j = 0; j < d; ++j) f += z[1 + j] * dirs[j];
    EXPECT_NEAR(z[0], gh, 1e-15) << "the normal impulse holds the weight";
    if (p < mu * gh) {
      EXPECT_NEAR(f.x(), -p, 1e-15) << "it sticks";
      EXPECT_NEAR(z[n - 1], 0.0, 1e-15);
    } else {
      EXPECT_NEAR(f.x(), -mu * gh, 1e-15) << "it slides, the friction at the cone's edge";
      EXPECT_NEAR(z[n - 1], p - mu * gh, 1e-15) << "at the speed left";
    }
    EXPECT_NEAR(f.y(), 0.0, 1e-15);
  }
}

// Degenerate: four redundant normals (a box's corners on a plane carry three dofs) with the active
// set's small regularisation: it ends, with the even split.
TEST(Lemke, EndsOnRedundantNormals) {
  const int n = 4;
  MatrixX J(3, 4);  // rows: the box's z, roll, pitch; columns: the corners at (+-1, +-1)
  J << 1, 1, 1, 1, 1, -1, 1, -1, 1, 1, -1, -1;
  const MatrixX M = J.transpose() * J + 1e-12 * 4.0 * MatrixX::Identity(n, n);
  const VectorX q = VectorX::Constant(n, -1.0);  // falling at 1: each corner's row
  Lemke lemke(n);
  VectorX z(n);
  ASSERT_TRUE(lemke.solve(M, q, n, z));
  EXPECT_LE(violation(M, q, z), 1e-9);
  for (int i = 0; i < n; ++i) EXPECT_NEAR(z[i], 0.25, 1e-9) << "the even split";
}

TEST(Lemke, SaysSoWhereThereIsNoAnswer) {
  // w = -z - 1 >= 0 has no z >= 0: a ray.
  MatrixX M(1, 1);
  M << -1.0;
  VectorX q(1);
  q << -1.0;
  Lemke lemke(2);
  VectorX z(1);
  EXPECT_FALSE(lemke.solve(M, q, 1, z));
  // Too large for its tableau.
  EXPECT_FALSE(lemke.solve(MatrixX::Identity(3, 3), VectorX::Constant(3, -1.0), 3, z = VectorX(3)));
  // q >= 0: z = 0 at once.
  ASSERT_TRUE(lemke.solve(MatrixX::Identity(2, 2), VectorX::Constant(2, 1.0), 2, z = VectorX(2)));
  EXPECT_EQ(z, VectorX::Zero(2));
  EXPECT_EQ(lemke.pivots(), 0);
}

}  // namespace
}  // namespace igms
