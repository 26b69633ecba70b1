// Push (eq. 3) and pull (eq. 4) force laws, and the tip's penetration into
// boxes, cylinders and spheres against analytic cases.
#include <gtest/gtest.h>

#include "core/interaction/pull.h"
#include "core/interaction/push.h"

namespace igms {
namespace {

CollisionShape box(double x, double y, double z) {
  CollisionShape s;
  s.kind = CollisionShape::Kind::Box;
  s.size = Vector3(x, y, z);
  return s;
}

TEST(TipContact, SphereTipAgainstBoxFace) {
  // Box 0.2 x 0.2 x 0.2 at the origin; tip of radius 0.01 centred 0.005 above the top face.
  const TipContact c = tipContact(box(0.2, 0.2, 0.2), SE3::Identity(), Vector3(0.03, -0.02, 0.105), 0.01);
  ASSERT_TRUE(c.touching);
  EXPECT_NEAR(c.depth, 0.005, 1e-15);
  EXPECT_LE((c.normal - Vector3::UnitZ()).norm(), 1e-15);
  EXPECT_LE((c.point - Vector3(0.03, -0.02, 0.1)).norm(), 1e-15);
}

TEST(TipContact, SphereTipInsideRotatedBoxLeavesByNearestFace) {
  SE3 pose;
  pose.R = Eigen::AngleAxisd(M_PI / 2, Vector3::UnitZ()).toRotationMatrix();
  pose.p = Vector3(1, 0, 0);
  // 0.02 inside the face whose world normal is +y (box x axis rotated onto y).
  const TipContact c = tipContact(box(0.2, 0.4, 0.4), pose, Vector3(1.0, 0.08, 0.0), 0.01);
  ASSERT_TRUE(c.touching);
  EXPECT_NEAR(c.depth, 0.03, 1e-12);
  EXPECT_LE((c.normal - Vector3::UnitY()).norm(), 1e-12);
}

TEST(TipContact, SphereTipAgainstCylinderSideAndCap) {
  CollisionShape cyl;
  cyl.kind = CollisionShape::Kind::Cylinder;
  cyl.size = Vector3(0.05, 0.4, 0);  // radius, length along z
  const TipContact side = tipContact(cyl, SE3::Identity(), Vector3(0.0, 0.056, 0.1), 0.01);
  ASSERT_TRUE(side.touching);
  EXPECT_NEAR(side.depth, 0.004, 1e-12);
  EXPECT_LE((side.normal - Vector3::UnitY()).norm(), 1e-12);
  const TipContact cap = tipContact(cyl, SE3::Identity(), Vector3(0.01, 0.0, -0.205), 0.01);
  ASSERT_TRUE(cap.touching);
  EXPECT_NEAR(cap.depth, 0.005, 1e-12);
  EXPECT_LE((cap.normal + Vector3::UnitZ()).norm(), 1e-12);
  EXPECT_FALSE(tipContact(cyl, SE3::Identity(), Vector3(0.0, 0.07, 0.0), 0.01).touching);
}

TEST(PushForce, IsStiffnessTimesDepthIntoTheLinkAndClamped) {
  TipContact c;
  c.touching = true;
  c.depth = 0.004;
  c.normal = Vector3(0, 0, 1);
  c.point = Vector3(1, 2, 3);
  const PushForce p = pushForce(c, 2000.0, 50.0);
  EXPECT_LE((p.on_link - Vector3(0, 0, -8.0)).norm(), 1e-12);  // c = k_p d = 8 N, pressing in
  EXPECT_FALSE(p.clamped);
  const PushForce q = pushForce(c, 2e5, 50.0);
  EXPECT_NEAR(q.on_link.norm(), 50.0, 1e-12);
  EXPECT_TRUE(q.clamped);
}

TEST(PullForce, IsSpringDamperWithCappedStretch) {
  const Vector3 x(0, 0, 0), xd(0.1, 0, 0);
  const PullForce f = pullForce(500, 10, 0.1, 100, Vector3(0.02, 0, 0), Vector3::Zero(), x, xd);
  // k (x_ph - x) + b (xd_ph - xd) = 500 * 0.02 - 10 * 0.1 = 9 N along x.
  EXPECT_LE((f.on_robot - Vector3(9.0, 0, 0)).norm(), 1e-12);
  // A device jump of 1 m stretches the spring only to max_stretch.
  const PullForce g = pullForce(500, 0, 0.1, 1000, Vector3(0, 1.0, 0), Vector3::Zero(), x, Vector3::Zero());
  EXPECT_TRUE(g.stretch_capped);
  EXPECT_NEAR(g.on_robot.norm(), 50.0, 1e-12);
  const PullForce h = pullForce(500, 0, 0.1, 20, Vector3(0, 1.0, 0), Vector3::Zero(), x, Vector3::Zero());
  EXPECT_TRUE(h.clamped);
  EXPECT_NEAR(h.on_robot.norm(), 20.0, 1e-12);
}

TEST(PullForce, DampingIsPassive) {
  // Device held still, robot point moving: the damper opposes the motion.
  const PullForce f = pullForce(0.0, 10, 0.1, 100, Vector3::Zero(), Vector3::Zero(), Vector3::Zero(), Vector3(1, 0, 0));
  EXPECT_LT(f.on_robot.dot(Vector3(1, 0, 0)), 0.0);
}

}  // namespace
}  // namespace igms
