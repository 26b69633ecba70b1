// Stiff couplings at 1 ms (a pull spring or push contact on a light link): the
// explicit schemes' measured stability limits match theory, and the
// linearly-implicit scheme stays stable and passive up to k = 1e7 N/m on 0.1 kg.
#include <gtest/gtest.h>

#include <cmath>

#include "tools/accuracy/step_matrix.h"
#include "tools/accuracy/stiffness.h"

namespace igms::accuracy {
namespace {

TEST(StiffCoupling, ExplicitLimitsMatchTheory) {
  EXPECT_NEAR(stabilityLimit(0, 0.1, 1e-3), 4.0, 0.05) << "semi-implicit Euler: k h^2 / m < 4";
  EXPECT_NEAR(stabilityLimit(1, 0.1, 1e-3), 8.0, 0.15) << "RK4: k h^2 / m < (2 sqrt 2)^2";
}

// The same limits read off each scheme's step matrix: exact, undamped and damped.
TEST(StiffCoupling, StepMatricesGiveTheLimitsExactly) {
  EXPECT_NEAR(spectralStabilityLimit(0, 0.0), 4.0, 1e-6) << "semi-implicit Euler";
  EXPECT_NEAR(spectralStabilityLimit(1, 0.0), 8.0, 1e-6) << "RK4: (2 sqrt 2)^2";
  const double critical = spectralStabilityLimit(0, 1.0);
  EXPECT_GT(critical, 0.6) << "explicit damping lowers semi-implicit Euler's limit";
  EXPECT_LT(critical, 0.75);
  for (double zeta : {0.0, 0.1, 1.0})
    EXPECT_TRUE(std::isinf(spectralStabilityLimit(2, zeta))) << "linearly implicit, zeta " << zeta;
  for (double ratio : {0.01, 1.0, 4.0, 100.0, 1e4})
    EXPECT_NEAR(stepSpectralRadius(2, ratio, 0.0), linearlyImplicitTheory(ratio), 1e-12) << ratio;
  EXPECT_NEAR(stepSpectralRadius(2, 100.0, 0.0), 0.0995, 5e-5) << "stable, and heavily damped";
  EXPECT_NEAR(stepSpectralRadius(0, 2.0, 0.0), 1.0, 1e-12) << "symplectic below its limit: no damping";
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
