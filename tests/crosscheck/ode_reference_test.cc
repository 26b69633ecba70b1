// igms against ODE, the independent reference: both simulate the same robot
// (ODE's first-order errors shrink in proportion to h towards igms's RK4 ground
// truth), igms's integrators converge at their order, and a free body keeps
// its momentum. The short version of igms-accuracy (the full sweep:
// scripts/reports/accuracy.sh).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/support/test_models.h"
#include "tools/accuracy/accuracy.h"
#include "tools/ode_ref/ode_robot.h"

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

// The PUMA's massless link 1 turns about a fixed axis: ODE gets 1 kg on that
// axis, which leaves the motion as it is, and QuickStep converges with
// dWorldStep (with 1e-6 kg it broke down).
TEST(OdeReference, QuickStepConvergesOnThePumaWithItsLink1Regularised) {
  Fixture f("puma_swing");
  const Errors quick1 = f.at(Method::OdeQuick, 1.0), quick05 = f.at(Method::OdeQuick, 0.5);
  const Errors world1 = f.at(Method::Ode, 1.0);
  const double o = order(quick1.ee_max, quick05.ee_max);
  std::printf("puma_swing: ODE QuickStep end-effector error %.3g m at 1 ms, %.3g at 0.5 ms (order %.2f); "
              "dWorldStep %.3g at 1 ms\n", quick1.ee_max, quick05.ee_max, o, world1.ee_max);
  EXPECT_NEAR(o, 1.0, 0.35);
  EXPECT_NEAR(quick1.ee_max, world1.ee_max, 0.2 * world1.ee_max) << "100 iterations: QuickStep meets dWorldStep";
  OdeSettings s;
  s.quickstep = true;
  const OdeRobot robot(*f.c.model, f.c.q0, f.c.v0, s);
  ASSERT_EQ(robot.regularised().size(), 1u);
  EXPECT_NE(robot.regularised()[0].find("link1 (1 kg on its fixed axis"), std::string::npos) << robot.regularised()[0];
}

// A hand held on the PUMA through the server's own step: the undamped pull
// keeps the energy (kinetic + gravity + spring) to the order of each scheme,
// and the linearly-implicit scheme removes energy from the spring mode as
// its step matrix says it must.
TEST(OdeReference, TheHandsCasesConserveOrDissipateAsEachSchemeShould) {
  Fixture f("puma_pull_k8000");
  const Errors rk4 = f.at(Method::Rk4, 1.0), sie = f.at(Method::SemiImplicitEuler, 1.0),
               li = f.at(Method::LinearlyImplicit, 1.0), li05 = f.at(Method::LinearlyImplicit, 0.5);
  std::printf("puma_pull_k8000, 1 ms: energy drift RK4 %.2e, semi-implicit Euler %.2e, linearly implicit %.2e "
              "(%+.3g W); joint error %.2e / %.2e / %.2e; k h^2/m %.3g\n",
              rk4.energy_drift, sie.energy_drift, li.energy_drift, li.energy_rate, rk4.q_max, sie.q_max, li.q_max,
              handStiffnessRatio(f.c));
  EXPECT_LT(rk4.energy_drift, 1e-5);
  EXPECT_LT(rk4.q_max, 1e-4);
  EXPECT_LT(sie.energy_drift, 0.05) << "symplectic: bounded";
  EXPECT_LT(li.energy_rate, -1.0) << "the implicit coupling damps the spring mode: watts, not round-off";
  EXPECT_GT(li.energy_rate, 2.0 * li05.energy_rate) << "and its damping vanishes with h";
  EXPECT_NEAR(handStiffnessRatio(f.c), 8000 * 1e-6 / 1.92, 0.1 * 8000 * 1e-6 / 1.92)
      << "the PUMA's effective mass at the end effector in its lightest direction is about 1.9 kg";
  Fixture push("puma_push_k2000");
  const Errors p1 = push.at(Method::Rk4, 1.0), p05 = push.at(Method::Rk4, 0.5);
  std::printf("puma_push_k2000: RK4 joint error %.2e at 1 ms, %.2e at 0.5 ms\n", p1.q_max, p05.q_max);
  EXPECT_LT(p05.q_max, p1.q_max) << "the push contact converges as the step shrinks";
  EXPECT_LT(p1.q_max, 3e-4) << "RK4 at 1 ms across contact transitions";
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
