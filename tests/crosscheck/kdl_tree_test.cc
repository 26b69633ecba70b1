// igms vs KDL's tree solvers on branched robots: the quadruped (fixed trunk)
// and random trees with branches, prismatic, continuous and fixed joints.
#include <gtest/gtest.h>

#include <kdl/treefksolverpos_recursive.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>
#include <kdl/treejnttojacsolver.hpp>
#include <limits>

#include "core/dynamics/external_force.h"
#include "core/dynamics/rnea.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/model/configuration.h"
#include "tests/support/kdl_convert.h"
#include "tests/support/kdl_from_urdf.h"
#include "tests/support/test_models.h"
#include "tests/support/tolerances.h"

namespace igms::test {
namespace {

class KdlTree : public ::testing::TestWithParam<NamedUrdf> {};

TEST_P(KdlTree, MatchesKdlTreeSolvers) {
  const NamedUrdf& robot = GetParam();
  const Model model = modelFromUrdf(robot.xml);
  Data data(model), poisoned(model);
  const KdlRobot kdl = kdlFromUrdf(robot.xml);
  ASSERT_EQ(static_cast<int>(kdl.tree.getNrOfJoints()), model.nv);
  const JointMap map = jointMap(model, kdl.q_nr_of_joint);

  KDL::TreeIdSolver_RNE id(kdl.tree, KDL::Vector(0, 0, -9.81));
  KDL::TreeFkSolverPos_recursive fk(kdl.tree);
  KDL::TreeJntToJacSolver jac(kdl.tree);
  std::mt19937 rng(11);
  std::vector<Force> fext(static_cast<size_t>(model.nb));
  double worst_fk = 0, worst_jac = 0, worst_frame_jac = 0, worst_id = 0;
  for (int s = 0; s < 100; ++s) {
    const VectorX q = randomConfiguration(model, rng);
    const VectorX v = randomVector(model.nv, rng, 2.0);
    const VectorX a = randomVector(model.nv, rng, 5.0);
    const KDL::JntArray kq = toKdl(q, map), kv = toKdl(v, map), ka = toKdl(a, map);
    forwardKinematics(model, data, q);
    for (size_t f = 0; f < model.frames.size(); ++f) {
      KDL::Frame F;
      ASSERT_GE(fk.JntToCart(kq, F, model.frames[f].name), 0);
      worst_fk = std::max(worst_fk, poseError(data.oMf[f], F));
    }
    // Jacobian of every leaf.
    for (const auto& leaf : kdl.leaves) {
      KDL::Jacobian kJ(kdl.tree.getNrOfJoints());
      ASSERT_GE(jac.JntToJac(kq, kJ, leaf), 0);
      pointJacobian(model, data, model.frameIndex(leaf), Vector3::Zero(), data.J);
      // KDL's tree Jacobian is referenced at the tip but expressed... in the base frame.
      worst_jac = std::max(worst_jac, relError(fromKdl(kJ.data, map), data.J));
      // frameJacobian places the frame's support itself, and nothing else: every pose poisoned first.
      for (SE3& X : poisoned.oMi) X.p.setConstant(std::numeric_limits<double>::quiet_NaN());
      frameJacobian(model, poisoned, q, model.frameIndex(leaf), poisoned.J);
      worst_frame_jac = std::max(worst_frame_jac, relError(fromKdl(kJ.data, map), poisoned.J));
    }
    // External point forces on three random links.
    clearExternalForces(fext);
    KDL::WrenchMap wrenches;
    for (int e = 0; e < 3; ++e) {
      const int f = static_cast<int>(rng() % model.frames.size());
      const PointForce pf{f, randomVector(3, rng, 0.3), randomVector(3, rng, 20.0)};
      addPointForce(model, data, pf, fext);
      KDL::Frame F;
      fk.JntToCart(kq, F, model.frames[static_cast<size_t>(f)].name);
      const std::string& name = model.frames[static_cast<size_t>(f)].name;
      if (name == model.root_link) continue;  // KDL's root is not a segment with a wrench
      wrenches[name] = (wrenches.count(name) ? wrenches[name] : KDL::Wrench::Zero()) +
                       wrenchOnSegment(F, pf.point, pf.force);
    }
    KDL::JntArray ktau(kdl.tree.getNrOfJoints());
    ASSERT_GE(id.CartToJnt(kq, kv, ka, wrenches, ktau), 0);
    worst_id = std::max(worst_id, relError(rnea(model, data, q, v, a, &fext), fromKdl(ktau, map)));
  }
  EXPECT_LE(worst_fk, kCrossCheckRel) << robot.name;
  EXPECT_LE(worst_jac, kCrossCheckRel) << robot.name;
  EXPECT_LE(worst_frame_jac, kCrossCheckRel) << robot.name;
  EXPECT_LE(worst_id, kCrossCheckRel) << robot.name;
}

INSTANTIATE_TEST_SUITE_P(Robots, KdlTree, ::testing::ValuesIn(branchedRobots(20)),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace igms::test
