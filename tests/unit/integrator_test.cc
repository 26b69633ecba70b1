// Integrators: convergence order on a pendulum; the linearly-implicit scheme
// stays stable on a stiff spring where semi-implicit Euler diverges.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/integrate/integrators.h"
#include "core/integrate/passive_joint_dynamics.h"
#include "core/scene/scene.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

// A pendulum: one revolute joint about y, 1 kg at 0.5 m, small inertia.
const char* kPendulum =
    "<robot name=\"pendulum\"><link name=\"base\"/><link name=\"bob\"><inertial><origin xyz=\"0 0 -0.5\"/>"
    "<mass value=\"1\"/><inertia ixx=\"1e-3\" ixy=\"0\" ixz=\"0\" iyy=\"1e-3\" iyz=\"0\" izz=\"1e-3\"/></inertial>"
    "</link><joint name=\"hinge\" type=\"continuous\"><parent link=\"base\"/><child link=\"bob\"/>"
    "<axis xyz=\"0 1 0\"/><dynamics damping=\"0.05\"/></joint></robot>";


double simulate(const Model& m, IntegratorKind kind, double h, double T, double spring_k = 0.0,
                double q0 = 1.0) {
  PassiveJointDynamics f(m, /*joint_damping=*/true, spring_k);
  IntegratorScratch<PassiveJointDynamics::Evaluation> s(m, f);
  VectorX q = VectorX::Constant(m.nq, q0), v = VectorX::Zero(m.nv);
  const int n = static_cast<int>(std::lround(T / h));
  for (int k = 0; k < n; ++k) {
    EXPECT_TRUE(integrateStep(kind, m, f, q, v, h, s));
    if (!q.allFinite() || std::abs(q[0]) > 1e6) return INFINITY;
  }
  return q[0];
}

double observedOrder(IntegratorKind kind) {
  const Model m = modelFromUrdf(kPendulum);
  const double reference = simulate(m, IntegratorKind::Rk4, 1e-5, 1.0);
  const double e1 = std::abs(simulate(m, kind, 4e-3, 1.0) - reference);
  const double e2 = std::abs(simulate(m, kind, 2e-3, 1.0) - reference);
  const double order = std::log2(e1 / e2);
  std::printf("%s: error %.3g at h = 4 ms, %.3g at 2 ms, observed order %.3f\n", integratorName(kind), e1, e2, order);
  return order;
}

TEST(Integrators, SemiImplicitEulerIsFirstOrder) { EXPECT_NEAR(observedOrder(IntegratorKind::SemiImplicitEuler), 1.0, 0.15); }
TEST(Integrators, Rk4IsFourthOrder) { EXPECT_NEAR(observedOrder(IntegratorKind::Rk4), 4.0, 0.3); }
TEST(Integrators, LinearlyImplicitEulerIsFirstOrder) { EXPECT_NEAR(observedOrder(IntegratorKind::LinearlyImplicit), 1.0, 0.15); }

TEST(Integrators, LinearlyImplicitStaysStableOnAStiffSpringWhereSemiImplicitEulerDiverges) {
  // A 0.1 kg slider on a k = 1e6 N/m spring at h = 1 ms: k h^2 / m = 10 > 4.
  const char* slider =
      "<robot name=\"slider\"><link name=\"base\"/><link name=\"mass\"><inertial><mass value=\"0.1\"/>"
      "<inertia ixx=\"1e-5\" ixy=\"0\" ixz=\"0\" iyy=\"1e-5\" iyz=\"0\" izz=\"1e-5\"/></inertial></link>"
      "<joint name=\"slide\" type=\"prismatic\"><parent link=\"base\"/><child link=\"mass\"/><axis xyz=\"1 0 0\"/>"
      "<limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint></robot>";
  BuildOptions o;
  o.gravity = Vector3::Zero();
  const Model m = buildModel(parseUrdfDescription(slider), o);
  EXPECT_TRUE(std::isinf(simulate(m, IntegratorKind::SemiImplicitEuler, 1e-3, 1.0, 1e6, 0.01)));
  const double x = simulate(m, IntegratorKind::LinearlyImplicit, 1e-3, 1.0, 1e6, 0.01);
  EXPECT_TRUE(std::isfinite(x));
  EXPECT_LE(std::abs(x), 0.01);  // dissipative: never beyond the start
  // Below the limit (k h^2 / m = 3.6) semi-implicit Euler is stable.
  EXPECT_TRUE(std::isfinite(simulate(m, IntegratorKind::SemiImplicitEuler, 1e-3, 1.0, 3.6e5, 0.01)));
}

}  // namespace
}  // namespace igms::test
