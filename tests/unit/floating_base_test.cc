// The floating base (6-dof free joint, quaternion, body-frame velocity) against
// the same robot mounted on 6 virtual joints (x, y, z prismatic, then z, y, x
// revolute through massless links): the code paths share nothing but the
// recursions. Also: momentum conservation of a free body in zero gravity.
#include <gtest/gtest.h>

#include "core/dynamics/aba.h"
#include "core/dynamics/crba.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/rnea.h"
#include "core/integrate/integrators.h"
#include "core/integrate/passive_joint_dynamics.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/model/configuration.h"
#include "tests/support/test_models.h"
#include "tests/support/tolerances.h"

namespace igms::test {
namespace {

// The same URDF with its root hung from world on 6 virtual joints.
std::string onVirtualJoints(const std::string& xml, const std::string& root) {
  const size_t body = xml.find('>', xml.find("<robot")) + 1;
  std::string v =
      "<link name=\"vworld\"/><link name=\"vx\"/><link name=\"vy\"/><link name=\"vz\"/><link name=\"vrz\"/>"
      "<link name=\"vry\"/>";
  const char* names[6] = {"vx", "vy", "vz", "vrz", "vry", root.c_str()};
  const char* parents[6] = {"vworld", "vx", "vy", "vz", "vrz", "vry"};
  const char* types[6] = {"prismatic", "prismatic", "prismatic", "continuous", "continuous", "continuous"};
  const char* axes[6] = {"1 0 0", "0 1 0", "0 0 1", "0 0 1", "0 1 0", "1 0 0"};
  for (int k = 0; k < 6; ++k) {
    v += std::string("<joint name=\"virtual") + std::to_string(k) + "\" type=\"" + types[k] + "\"><parent link=\"" +
         parents[k] + "\"/><child link=\"" + names[k] + "\"/><axis xyz=\"" + axes[k] + "\"/>" +
         (k < 3 ? "<limit lower=\"-10\" upper=\"10\" effort=\"1\" velocity=\"1\"/>" : "") + "</joint>";
  }
  return xml.substr(0, body) + v + xml.substr(body);
}

class FloatingBase : public ::testing::TestWithParam<NamedUrdf> {};

TEST_P(FloatingBase, MatchesSixVirtualJoints) {
  const Model fb = modelFromUrdf(GetParam().xml, true);
  const Model vj = modelFromUrdf(onVirtualJoints(GetParam().xml, fb.root_link), false);
  ASSERT_EQ(vj.nv, fb.nv);
  Data dfb(fb), dvj(vj);
  const int base = vj.jointIndex("virtual5");  // its body is the robot's root body
  ASSERT_GE(base, 0);
  std::mt19937 rng(3);
  double worst_joint = 0, worst_base = 0, worst_fd = 0;
  for (int s = 0; s < 100; ++s) {
    const VectorX qv = randomConfiguration(vj, rng), vv = randomVector(vj.nv, rng), av = randomVector(vj.nv, rng);
    const VectorX tau_v = rnea(vj, dvj, qv, vv, av);
    // The base's pose, body velocity and true body acceleration on the virtual chain.
    forwardKinematics(vj, dvj, qv);
    rnea(vj, dvj, qv, vv, av);
    const SE3 X = dvj.oMi[base];
    const Motion vb = dvj.v[base];
    Motion ab = dvj.a[base];
    ab.v += X.R.transpose() * vj.gravity;  // remove the gravity folded into a
    Eigen::Quaterniond quat(X.R);
    VectorX qf(fb.nq), vf(fb.nv), af(fb.nv);
    qf << X.p, quat.w(), quat.x(), quat.y(), quat.z(), VectorX::Zero(fb.nq - 7);
    vf << vb.v, vb.w, VectorX::Zero(fb.nv - 6);
    af << ab.v, ab.w, VectorX::Zero(fb.nv - 6);
    // Joint coordinates: map by name.
    for (int i = 0; i < fb.nb; ++i) {
      if (fb.joint_type[i] == JointType::Floating) continue;
      const int j = vj.jointIndex(fb.joint_name[i]);
      qf[fb.q_index[i]] = qv[vj.q_index[j]];
      vf[fb.v_index[i]] = vv[vj.v_index[j]];
      af[fb.v_index[i]] = av[vj.v_index[j]];
    }
    const VectorX tau_f = rnea(fb, dfb, qf, vf, af);
    // G: the virtual joints' subspaces seen in the base body frame; their
    // torques are G^T (base wrench).
    Eigen::Matrix<double, 6, 6> Gm;
    for (int k = 0; k < 6; ++k) {
      VectorX e = VectorX::Zero(vj.nv);
      e[k] = 1.0;
      rnea(vj, dvj, qv, e, VectorX::Zero(vj.nv));
      Gm.col(k) = dvj.v[base].toVector();
    }
    worst_base = std::max(worst_base, relError(Gm.transpose() * tau_f.head<6>(), tau_v.head<6>()));
    for (int i = 0; i < fb.nb; ++i) {
      if (fb.joint_type[i] == JointType::Floating) continue;
      const int j = vj.jointIndex(fb.joint_name[i]);
      worst_joint = std::max(worst_joint, std::abs(tau_f[fb.v_index[i]] - tau_v[vj.v_index[j]]) /
                                              std::max(1.0, std::abs(tau_v[vj.v_index[j]])));
    }
    // Forward dynamics of the free robot reproduces af from tau_f.
    ASSERT_TRUE(forwardDynamics(fb, dfb, qf, vf, tau_f));
    worst_fd = std::max(worst_fd, relError(dfb.qdd, af));
  }
  EXPECT_LE(worst_base, kCrossCheckRel);
  EXPECT_LE(worst_joint, kCrossCheckRel);
  EXPECT_LE(worst_fd, kIdentityRel);
}

TEST_P(FloatingBase, FreeRobotConservesMomentumInZeroGravity) {
  // No external force, no gravity, zero torques: the spatial momentum about
  // the world origin, in world axes, is constant. Integrated with igms's RK4.
  BuildOptions o;
  o.floating_base = true;
  o.gravity = Vector3::Zero();
  const Model m = buildModel(parseUrdfDescription(GetParam().xml), o);
  Data d(m);
  std::mt19937 rng(5);
  VectorX q = randomConfiguration(m, rng), v = randomVector(m.nv, rng, 1.0);
  auto momentum = [&](const VectorX& qq, const VectorX& vv) {
    rnea(m, d, qq, vv, VectorX::Zero(m.nv));  // fills v and oMi via liMi
    bodyKinematics(m, d, qq);
    Force total;
    for (int i = 0; i < m.nb; ++i) total += d.oMi[i].act(m.inertia[i] * d.v[i]);
    return total.toVector();
  };
  const Vector6 h0 = momentum(q, v);
  PassiveJointDynamics free_motion(m, false);
  IntegratorScratch<PassiveJointDynamics::Evaluation> scratch(m, free_motion);
  for (int step = 0; step < 1000; ++step) stepRk4(m, free_motion, q, v, 1e-3, scratch);
  const Vector6 h1 = momentum(q, v);
  // Fourth order on the group (RKMK): the drift over 1 s at 1 ms is of the
  // order of the local error (worst 1.2e-11 relative over 11 robots).
  EXPECT_LE((h1 - h0).norm(), 1e-9 * std::max(1.0, h0.norm())) << "h0 " << h0.transpose() << "\nh1 " << h1.transpose();
}

// Robots whose root link has mass (a massless root on a revolute joint makes a
// floating base singular: the two can counter-rotate at zero kinetic energy).
std::vector<NamedUrdf> floatingRobots() {
  std::vector<NamedUrdf> out = branchedRobots(6);
  for (const auto& r : serialRobots(4))
    if (r.name.rfind("random", 0) == 0) out.push_back(r);
  return out;
}

INSTANTIATE_TEST_SUITE_P(Robots, FloatingBase, ::testing::ValuesIn(floatingRobots()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace igms::test
