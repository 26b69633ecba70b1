// igms against ODE, the independent reference: both simulate the same robot
// (ODE's first-order errors shrink in proportion to h towards igms's RK4 ground
// truth), igms's integrators converge at their order, and a free body keeps
// its momentum. The short version of igms-accuracy (the full sweep:
// scripts/accuracy.sh).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/support/test_models.h"
#include "tools/accuracy/accuracy.h"

namespace igms::accuracy {
namespace {

double order(double e_coarse, double e_fine) { return std::log2(e_coarse / e_fine); }

struct Fixture {
  Case c;
  Run truth;
  explicit Fixture(const std::string& name) : c(makeCase(name, test::sourceDir())) {
    c.duration = 1.024;
    truth = simulate(c, Method::Rk4, 1.0 / 64 * 1e-3);
  }
  Errors at(Method m, double h_ms) { return compare(c, simulate(c, m, h_ms * 1e-3), truth); }
};

TEST(OdeReference, IgmsIntegratorsConvergeAtTheirOrderOnThePuma) {
  Fixture f("puma_swing");
  const double rk4 = order(f.at(Method::Rk4, 2.0).q_max, f.at(Method::Rk4, 1.0).q_max);
  const double sie = order(f.at(Method::SemiImplicitEuler, 1.0).q_max, f.at(Method::SemiImplicitEuler, 0.5).q_max);
  const double li = order(f.at(Method::LinearlyImplicit, 1.0).q_max, f.at(Method::LinearlyImplicit, 0.5).q_max);
  std::printf("observed orders on the PUMA: RK4 %.2f, semi-implicit Euler %.2f, linearly implicit %.2f\n", rk4, sie, li);
  EXPECT_NEAR(rk4, 4.0, 0.4);
  EXPECT_NEAR(sie, 1.0, 0.2);
  EXPECT_NEAR(li, 1.0, 0.2);
}

TEST(OdeReference, OdeConvergesToIgmsGroundTruthAtFirstOrder) {
  for (const char* name : {"puma_swing", "tumble"}) {
    Fixture f(name);
    const Errors e1 = f.at(Method::Ode, 1.0), e05 = f.at(Method::Ode, 0.5), e025 = f.at(Method::Ode, 0.25);
    const double o = order(e05.ee_max, e025.ee_max);
    std::printf("%s: ODE dWorldStep end-effector error %.3g m at 1 ms, %.3g at 0.5 ms, %.3g at 0.25 ms (order %.2f)\n",
                name, e1.ee_max, e05.ee_max, e025.ee_max, o);
    EXPECT_NEAR(o, 1.0, 0.35) << name << ": the same system, simulated to first order";
    EXPECT_LT(e025.ee_max, 1.5e-3) << name;
    EXPECT_LT(e1.energy_drift, 0.02) << name;
  }
}

TEST(OdeReference, AFreeBodyKeepsItsMomentum) {
  Fixture f("tumble");
  const Errors ode = f.at(Method::Ode, 1.0), rk4 = f.at(Method::Rk4, 1.0), sie = f.at(Method::SemiImplicitEuler, 1.0);
  std::printf("tumble, 1 ms: linear / angular momentum drift: ODE %.2e / %.2e, RK4 %.2e / %.2e, "
              "semi-implicit Euler %.2e / %.2e\n",
              ode.linear_momentum_drift, ode.angular_momentum_drift, rk4.linear_momentum_drift,
              rk4.angular_momentum_drift, sie.linear_momentum_drift, sie.angular_momentum_drift);
  EXPECT_LT(ode.linear_momentum_drift, 1e-9) << "maximal coordinates conserve linear momentum to round-off";
  EXPECT_LT(ode.angular_momentum_drift, 1e-3);
  EXPECT_LT(rk4.linear_momentum_drift, 1e-9);
  EXPECT_LT(rk4.angular_momentum_drift, 1e-9);
  EXPECT_LT(sie.linear_momentum_drift, 1e-2);
  // Fourth order on the floating base too (Runge-Kutta-Munthe-Kaas).
  const double rk4_order = order(f.at(Method::Rk4, 2.0).q_max, rk4.q_max);
  std::printf("tumble: RK4 order %.2f\n", rk4_order);
  EXPECT_NEAR(rk4_order, 4.0, 0.4);
}

}  // namespace
}  // namespace igms::accuracy
