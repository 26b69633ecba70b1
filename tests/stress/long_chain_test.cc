// Long chains (100 and 200 links): the digits forward dynamics achieves on
// FD(ID(a)) = a, and ABA against the LDL^T path, set against the conditioning
// of H. The bound: relative error <= cond(H) * 1e-15 * 100 (round-off grows
// with the condition number, not faster).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/support/fd_digits.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

class LongChain : public ::testing::TestWithParam<int> {};

TEST_P(LongChain, DigitsFollowTheConditioningOfH) {
  const FdDigits r = measureFdDigits(modelFromUrdf(serialChainUrdf(GetParam())), 5, 5, 1e-13);
  EXPECT_TRUE(r.within_bound) << "cond " << r.worst_cond << ", FD " << r.worst_fd << ", ABA " << r.worst_aba;
  std::printf("%d links: cond(H) up to %.3g; FD(ID(a)) relative error %.3g (%.1f digits); ABA vs LDL^T %.3g\n",
              GetParam(), r.worst_cond, r.worst_fd, -std::log10(r.worst_fd), r.worst_aba);
}

INSTANTIATE_TEST_SUITE_P(Links, LongChain, ::testing::Values(100, 200));

}  // namespace
}  // namespace igms::test
