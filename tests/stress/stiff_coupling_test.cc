// Stiff couplings at 1 ms (a pull spring or push contact on a light link): the
// explicit schemes' measured stability limits match theory, and the
// linearly-implicit scheme stays stable and passive up to k = 1e7 N/m on 0.1 kg.
#include <gtest/gtest.h>

#include "tools/accuracy/stiffness.h"

namespace igms::accuracy {
namespace {

TEST(StiffCoupling, ExplicitLimitsMatchTheory) {
  EXPECT_NEAR(stabilityLimit(0, 0.1, 1e-3), 4.0, 0.05) << "semi-implicit Euler: k h^2 / m < 4";
  EXPECT_NEAR(stabilityLimit(1, 0.1, 1e-3), 8.0, 0.15) << "RK4: k h^2 / m < (2 sqrt 2)^2";
}

TEST(StiffCoupling, LinearlyImplicitIsStableAndPassiveUpTo1e7) {
  std::vector<double> ks;
  for (double k = 100; k <= 1.01e7; k *= 10) ks.push_back(k);
  for (const auto& r : stiffnessSweep(0.1, 1e-3, ks)) {
    EXPECT_TRUE(r.stable[2]) << "k = " << r.k;
    EXPECT_LE(r.energy_ratio[2], 1.0 + 1e-12) << "energy never grows, k = " << r.k;
    if (r.k_h2_m > 8.5) {
      EXPECT_FALSE(r.stable[0]) << "semi-implicit Euler must blow up at k h^2/m = " << r.k_h2_m;
      EXPECT_FALSE(r.stable[1]) << "RK4 must blow up at k h^2/m = " << r.k_h2_m;
    }
  }
}

}  // namespace
}  // namespace igms::accuracy
