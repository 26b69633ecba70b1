// Extreme masses along a chain: from root to tip the masses fall by 1e3 and by
// 1e6, and chains of 1 g and of 1 t links. Forward dynamics keeps its digits within
// what cond(H) allows, and ABA agrees with the LDL^T path.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/support/fd_digits.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

struct Masses {
  const char* name;
  double base, ratio;
};

class MassRatio : public ::testing::TestWithParam<Masses> {};

TEST_P(MassRatio, ForwardDynamicsKeepsTheDigitsConditioningAllows) {
  const FdDigits r = measureFdDigits(modelFromUrdf(taperedChainUrdf(GetParam().base, GetParam().ratio)), 10, 9, 1e-13, 1e-12);
  EXPECT_TRUE(r.within_bound) << GetParam().name << ": cond " << r.worst_cond << ", FD " << r.worst_fd;
  std::printf("%-22s cond(H) up to %.3g; FD(ID(a)) relative error %.3g; ABA vs LDL^T %.3g\n", GetParam().name,
              r.worst_cond, r.worst_fd, r.worst_aba);
}

INSTANTIATE_TEST_SUITE_P(Chains, MassRatio,
                         ::testing::Values(Masses{"ratio_1e3", 1.0, 1e3}, Masses{"ratio_1e6", 1.0, 1e6},
                                           Masses{"links_of_1_g", 1e-3, 1.0}, Masses{"links_of_1_t", 1e3, 1.0}),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace igms::test
