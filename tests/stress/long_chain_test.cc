// Long chains (100 and 200 links): the digits forward dynamics achieves on
// FD(ID(a)) = a, and ABA against the LDL^T path, set against the conditioning
// of H. The bound: relative error <= cond(H) * 1e-15 * 100 (round-off grows
// with the condition number, not faster).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cstdio>

#include "server/dynamics/aba.h"
#include "server/dynamics/crba.h"
#include "server/dynamics/forward_dynamics.h"
#include "server/dynamics/rnea.h"
#include "server/model/configuration.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

class LongChain : public ::testing::TestWithParam<int> {};

TEST_P(LongChain, DigitsFollowTheConditioningOfH) {
  const Model m = modelFromUrdf(serialChainUrdf(GetParam()));
  Data d(m);
  std::mt19937 rng(5);
  double worst_fd = 0, worst_aba = 0, worst_cond = 0;
  for (int s = 0; s < 5; ++s) {
    const VectorX q = randomConfiguration(m, rng), v = randomVector(m.nv, rng), a = randomVector(m.nv, rng);
    const VectorX tau = rnea(m, d, q, v, a);
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<MatrixX>(crba(m, d, q)).eigenvalues();
    const double cond = ev.maxCoeff() / ev.minCoeff();
    ASSERT_TRUE(forwardDynamics(m, d, q, v, tau));
    const VectorX ldlt = d.qdd;
    const double fd = (ldlt - a).norm() / a.norm();
    ASSERT_TRUE(aba(m, d, q, v, tau));
    const double ab = (d.qdd - ldlt).norm() / ldlt.norm();
    EXPECT_LE(fd, cond * 1e-13) << "cond " << cond;
    EXPECT_LE(ab, cond * 1e-13) << "cond " << cond;
    worst_fd = std::max(worst_fd, fd);
    worst_aba = std::max(worst_aba, ab);
    worst_cond = std::max(worst_cond, cond);
  }
  std::printf("%d links: cond(H) up to %.3g; FD(ID(a)) relative error %.3g (%.1f digits); ABA vs LDL^T %.3g\n",
              GetParam(), worst_cond, worst_fd, -std::log10(worst_fd), worst_aba);
}

INSTANTIATE_TEST_SUITE_P(Links, LongChain, ::testing::Values(100, 200));

}  // namespace
}  // namespace igms::test
