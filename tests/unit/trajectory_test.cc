// Trajectories: the resume quintic meets its boundary conditions; the clamped
// spline is C2 at its knots; the Cartesian line keeps the frame on the line.
#include <gtest/gtest.h>

#include "core/kinematics/forward_kinematics.h"
#include "core/model_io/model_loader.h"
#include "core/trajectory/cartesian_line.h"
#include "core/trajectory/piecewise_polynomial.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

TEST(Trajectory, ResumeQuinticMatchesStateAtBothEnds) {
  VectorX q0(2), v0(2), a0(2), q1(2), z = VectorX::Zero(2);
  q0 << 0.3, -1.0;
  v0 << 0.5, 2.0;
  a0 << -3.0, 7.0;
  q1 << 1.2, 0.4;
  PiecewisePolynomial p(2, 1);
  p.setQuintic(2.0, 1.5, q0, v0, a0, q1, z, z);
  VectorX q(2), qd(2), qdd(2);
  p.evaluate(2.0 + 1e-12, q, qd, qdd);
  EXPECT_LE((q - q0).norm(), 1e-9);
  EXPECT_LE((qd - v0).norm(), 1e-9);
  EXPECT_LE((qdd - a0).norm(), 1e-9);
  p.evaluate(3.5 - 1e-12, q, qd, qdd);
  EXPECT_LE((q - q1).norm(), 1e-9);
  EXPECT_LE(qd.norm(), 1e-9);
  EXPECT_LE(qdd.norm(), 1e-8);
}

TEST(Trajectory, ClampedSplineIsC2AtKnotsAndRestsAtEnds) {
  std::vector<double> t{0.0, 0.4, 1.1, 1.5, 2.4};
  std::vector<VectorX> p;
  for (double x : {0.0, 0.7, -0.2, 0.5, 1.0}) p.push_back(VectorX::Constant(1, x));
  const PiecewisePolynomial s = PiecewisePolynomial::clampedCubicSpline(t, p);
  VectorX a(1), ad(1), add(1), b(1), bd(1), bdd(1);
  for (size_t k = 1; k + 1 < t.size(); ++k) {
    s.evaluate(t[k] - 1e-9, a, ad, add);
    s.evaluate(t[k] + 1e-9, b, bd, bdd);
    EXPECT_NEAR(a[0], p[k][0], 1e-8);
    EXPECT_NEAR(b[0], p[k][0], 1e-8);
    EXPECT_NEAR(ad[0], bd[0], 1e-7);
    EXPECT_NEAR(add[0], bdd[0], 1e-6);
  }
  s.evaluate(1e-12, a, ad, add);
  EXPECT_NEAR(ad[0], 0.0, 1e-9);
  s.evaluate(2.4 - 1e-12, a, ad, add);
  EXPECT_NEAR(ad[0], 0.0, 1e-9);
}

TEST(Trajectory, CartesianLineKeepsTheFrameOnTheLine) {
  const Model m = loadModel(sourceDir() + "/models/puma560.urdf");
  VectorX q0(6);
  q0 << -0.9, 0.6, -2.2, 0.0, 0.8, 0.0;
  CartesianLine line;
  line.frame = m.frameIndex("ee_link");
  line.target = Vector3(0.45, 0.50, 0.25);
  line.duration = 4.0;
  const PiecewisePolynomial traj = cartesianLineTrajectory(m, q0, line);
  Data d(m);
  forwardKinematics(m, d, q0);
  const Vector3 start = d.oMf[line.frame].p;
  const Vector3 dir = (line.target - start).normalized();
  VectorX q(6), qd(6), qdd(6);
  double worst = 0.0;
  for (int k = 0; k <= 400; ++k) {
    traj.evaluate(4.0 * k / 400, q, qd, qdd);
    forwardKinematics(m, d, q);
    const Vector3 r = d.oMf[line.frame].p - start;
    worst = std::max(worst, (r - r.dot(dir) * dir).norm());
  }
  EXPECT_LE(worst, 2e-4) << "off the line by " << worst << " m between IK samples";
  traj.evaluate(4.0, q, qd, qdd);
  forwardKinematics(m, d, q);
  EXPECT_LE((d.oMf[line.frame].p - line.target).norm(), 1e-6);
}

}  // namespace
}  // namespace igms::test
