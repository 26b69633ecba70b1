// The 6-D pull (eq. 4 with X a pose): the rotational spring-damper on SO(3),
// its torque through the 6 x n frame Jacobian, and the implicit step at the
// rotational stiffnesses a 6-dof device renders.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "core/dynamics/crba.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/joint_damping.h"
#include "core/interaction/pull.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/model/configuration.h"
#include "core/simulation/coupled_dynamics.h"
#include "core/simulation/simulation.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

Matrix3 rot(const Vector3& axis_angle) {
  const double a = axis_angle.norm();
  return a > 0 ? Eigen::AngleAxisd(a, axis_angle / a).toRotationMatrix() : Matrix3::Identity();
}

TEST(PullTorque, APureRotationErrorGivesTheTorqueAboutItsAxis) {
  const double k = 20.0;
  for (const Vector3& e : {Vector3(0, 0, 0.2), Vector3(0.1, 0, 0), Vector3(0.05, -0.1, 0.08)}) {
    // The grasped frame at some orientation R; the device turned by e (world axes) from it.
    const Matrix3 R = rot(Vector3(0.3, -0.7, 1.1));
    const PullTorque t = pullTorque(k, 0.0, 1.0, 1e9, rot(e) * R, Vector3::Zero(), R, Vector3::Zero());
    EXPECT_LE((t.on_robot - k * e).norm(), 1e-12) << e.transpose();
    EXPECT_FALSE(t.angle_capped);
    EXPECT_FALSE(t.clamped);
  }
}

TEST(PullTorque, DampingIsPassiveAndBothCapsHold) {
  // Device still, frame turning: the torque opposes the turning (the passive sign).
  const PullTorque d = pullTorque(0.0, 0.5, 1.0, 1e9, Matrix3::Identity(), Vector3::Zero(), Matrix3::Identity(),
                                  Vector3(0, 0, 2.0));
  EXPECT_LE((d.on_robot - Vector3(0, 0, -1.0)).norm(), 1e-12);
  // A 1.5 rad error is capped at 0.5 rad, and the torque at 3 N m.
  const PullTorque c = pullTorque(10.0, 0.0, 0.5, 1e9, rot(Vector3(1.5, 0, 0)), Vector3::Zero(), Matrix3::Identity(),
                                  Vector3::Zero());
  EXPECT_TRUE(c.angle_capped);
  EXPECT_NEAR(c.on_robot.x(), 5.0, 1e-12);
  const PullTorque m = pullTorque(10.0, 0.0, 0.5, 3.0, rot(Vector3(1.5, 0, 0)), Vector3::Zero(), Matrix3::Identity(),
                                  Vector3::Zero());
  EXPECT_TRUE(m.clamped);
  EXPECT_NEAR(m.on_robot.norm(), 3.0, 1e-12);
}

TEST(PullTorque, TheLogMapInvertsTheExponentialUpToPi) {
  for (const double angle : {1e-9, 1e-4, 0.3, 2.0, 3.1, M_PI - 1e-6}) {
    const Vector3 axis = Vector3(0.2, -0.5, 0.8).normalized();
    const Vector3 back = rotationLog(rot(angle * axis));
    EXPECT_LE((back - angle * axis).norm(), 1e-9 * std::max(1.0, angle)) << angle;
  }
}

// The angular rows of the point Jacobian (what carries the torque, tau = J^T [F; T]) against
// finite differences of the frame's orientation through the log map, on three robots.
TEST(PullTorque, TheFrameJacobiansAngularRowsMatchFiniteDifferencesOfTheLogMap) {
  const std::string dir = sourceDir() + "/models/";
  struct Case { std::string urdf; bool floating; };
  for (const Case& c : {Case{"puma560.urdf", false}, Case{"arm7.urdf", false}, Case{"quadruped.urdf", true}}) {
    const Model m = modelFromUrdf(readFile(dir + c.urdf), c.floating);
    Data d(m);
    std::mt19937 rng(7);
    const VectorX q = randomConfiguration(m, rng);
    const int f = static_cast<int>(m.frames.size()) - 1;
    Matrix6X J(6, m.nv);
    bodyKinematics(m, d, q);
    pointJacobian(m, d, f, Vector3(0.01, 0.02, 0.03), J);
    forwardKinematics(m, d, q);
    const Matrix3 R0 = d.oMf[static_cast<size_t>(f)].R;
    const double h = 1e-6;
    double worst = 0.0;
    for (int i = 0; i < m.nv; ++i) {
      VectorX dv = VectorX::Zero(m.nv);
      dv[i] = h;
      VectorX qp(m.nq), qm(m.nq);
      integrateConfiguration(m, q, dv, 1.0, qp);
      integrateConfiguration(m, q, dv, -1.0, qm);
      forwardKinematics(m, d, qp);
      const Matrix3 Rp = d.oMf[static_cast<size_t>(f)].R;
      forwardKinematics(m, d, qm);
      const Matrix3 Rm = d.oMf[static_cast<size_t>(f)].R;
      const Vector3 w = (rotationLog(Rp * R0.transpose()) - rotationLog(Rm * R0.transpose())) / (2 * h);
      worst = std::max(worst, (w - J.col(i).tail<3>()).norm());
    }
    EXPECT_LE(worst, 1e-8) << c.urdf;
  }
}

Scene pullScene(double k_rot) {
  Scene s = loadScene(sourceDir() + "/scenes/puma_wall.yaml");
  s.pull.enabled = true;
  s.pull.k_rot = k_rot;
  s.pull.b_rot = 0.2 * std::sqrt(k_rot) * 0.05;
  return s;
}

InteractionInput pose(const SE3& X, const Vector3& offset, const Vector3& turn) {
  InteractionInput in;
  in.mode = InteractionMode::Pull;
  in.tip_position = X.p + offset;
  in.has_orientation = true;
  in.tip_orientation = Eigen::Quaterniond(rot(turn) * X.R);
  in.seq = 1;
  in.client = 1;
  return in;
}

// tau = J^T [F; T]: the step's acceleration is forward dynamics under the generalised force of the
// wrench the outcome reports, at the start state (the explicit step's: its wrench is the start one;
// the linearly-implicit step reports the wrench it applied at its end, applied_force_test).
TEST(Pull6D, TheTorqueEntersTheDynamicsThroughTheFrameJacobian) {
  Scene s = pullScene(20.0);
  s.integrator = IntegratorKind::SemiImplicitEuler;
  Simulation sim(s);
  const int ee = sim.model().frameIndex("ee_link");
  const SE3 X = sim.linkPoses()[static_cast<size_t>(ee)];
  const InteractionInput in = pose(X, Vector3(0.01, 0, 0), Vector3(0, 0.1, 0.05));
  const VectorX q = sim.q(), v = sim.v();
  ASSERT_TRUE(sim.step(&in));
  const Vector3 T = sim.outcome().torque_on_robot, F = sim.outcome().force_on_robot;
  EXPECT_LE((T - 20.0 * Vector3(0, 0.1, 0.05)).norm(), 1e-9) << T.transpose();
  const Model& m = sim.model();
  Data d(m);
  Matrix6X J(6, m.nv);
  bodyKinematics(m, d, q);
  pointJacobian(m, d, ee, Vector3::Zero(), J);
  Vector6 w;
  w << F, T;
  VectorX tau = sim.tau() + J.transpose() * w;
  tau -= sim.scene().robots[0].hold_damping * [&] { return crba(m, d, q).symmetricUpperTimes(v); }();
  if (sim.scene().joint_damping) tau -= jointDamping(m).cwiseProduct(v);
  ASSERT_TRUE(forwardDynamics(m, d, q, v, tau));
  EXPECT_LE((d.qdd - sim.qdd()).norm(), 1e-9 * std::max(1.0, d.qdd.norm()));
}

TEST(Pull6D, APullHoldsTheEndEffectorsPose) {
  Simulation sim(pullScene(20.0));
  const int ee = sim.model().frameIndex("ee_link");
  const SE3 X = sim.linkPoses()[static_cast<size_t>(ee)];
  const Vector3 offset(0.03, -0.02, 0.02), turn(0.0, 0.25, -0.15);
  const InteractionInput in = pose(X, offset, turn);
  for (int k = 0; k < 4000; ++k) ASSERT_TRUE(sim.step(&in)) << sim.divergenceReport();
  const SE3 Y = sim.linkPoses()[static_cast<size_t>(ee)];
  const double position_error = (Y.p - in.tip_position).norm();
  const double angle_error = rotationLog(in.tip_orientation.toRotationMatrix() * Y.R.transpose()).norm();
  std::printf("6-D pull hold, PUMA, 4 s: position error %.2e m, angle error %.2e rad (asked: %.3f m, %.3f rad)\n",
              position_error, angle_error, offset.norm(), turn.norm());
  EXPECT_LE(position_error, 2e-3);
  EXPECT_LE(angle_error, 5e-3);
  // The 3-D pull leaves the orientation alone: the same run without k_rot ends turned away.
  Simulation plain(pullScene(0.0));
  for (int k = 0; k < 4000; ++k) ASSERT_TRUE(plain.step(&in));
  const SE3 Z = plain.linkPoses()[static_cast<size_t>(ee)];
  EXPECT_GT(rotationLog(in.tip_orientation.toRotationMatrix() * Z.R.transpose()).norm(), 0.1);
}

// With the device held still, no gravity, no controller and no damping anywhere, the energy
// E = 1/2 v^T H v + 1/2 k |x_ph - x|^2 + 1/2 k_rot |e|^2 may only fall: the linearly-implicit step
// stays passive from a soft to a very stiff rotational spring; the explicit step does not.
double energy(Simulation& sim, const InteractionInput& in, int ee) {
  const Model& m = sim.model();
  Data d(m);
  crba(m, d, sim.q());
  const SE3 X = sim.linkPoses()[static_cast<size_t>(ee)];
  const Vector3 e = rotationLog(in.tip_orientation.toRotationMatrix() * X.R.transpose());
  return 0.5 * sim.v().dot(d.H.symmetricUpperTimes(sim.v())) + 0.5 * sim.scene().pull.k * (in.tip_position - X.p).squaredNorm() +
         0.5 * sim.scene().pull.k_rot * e.squaredNorm();
}

TEST(Pull6D, TheImplicitStepStaysPassiveAtHighRotationalStiffness) {
  for (const double k_rot : {1.0, 10.0, 100.0, 1e3, 1e4, 1e5}) {
    for (const IntegratorKind kind : {IntegratorKind::LinearlyImplicit, IntegratorKind::SemiImplicitEuler}) {
      Scene s = pullScene(k_rot);
      s.robots[0].trajectory = TrajectorySpec{};
      s.gravity = Vector3::Zero();
      s.joint_damping = false;
      s.joint_limits = false;
      s.pull.b = 0.0;
      s.pull.b_rot = 0.0;
      s.pull.max_torque = 1e9;
      s.pull.max_force = 1e9;
      s.pull.max_angle = 3.0;
      s.pull.max_stretch = 10.0;
      s.integrator = kind;
      Simulation sim(s);
      const int ee = sim.model().frameIndex("ee_link");
      const InteractionInput in = pose(sim.linkPoses()[static_cast<size_t>(ee)], Vector3::Zero(), Vector3(0.2, 0.1, 0));
      const double E0 = energy(sim, in, ee);
      double E_max = E0;
      bool ok = true;
      for (int k = 0; k < 2000 && ok; ++k) {
        ok = sim.step(&in);
        if (ok) E_max = std::max(E_max, energy(sim, in, ee));
      }
      std::printf("k_rot %8.0f N m/rad, %-20s %s, max E / E0 = %.6f, final E / E0 = %.4f\n", k_rot,
                  integratorName(kind), ok ? "stable  " : "diverged", E_max / E0, ok ? energy(sim, in, ee) / E0 : NAN);
      if (kind == IntegratorKind::LinearlyImplicit) {
        EXPECT_TRUE(ok) << k_rot << ": " << sim.divergenceReport();
        EXPECT_LE(E_max, E0 * (1.0 + 1e-3)) << "k_rot " << k_rot;
        EXPECT_LT(energy(sim, in, ee), E0) << "k_rot " << k_rot;
      } else if (k_rot >= 1e4) {
        EXPECT_TRUE(!ok || E_max > 10.0 * E0) << "the explicit step at k_rot " << k_rot
                                             << " should gain energy: the test would not see a non-passive step";
      }
    }
  }
}

}  // namespace
}  // namespace igms::test
