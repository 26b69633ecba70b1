// igms vs KDL's chain solvers on the PUMA 560, the 7-dof arm and random chains
// (prismatic, continuous and fixed joints, rotated origins, tilted axes,
// massless intermediate links), 100 random states each.
#include <gtest/gtest.h>

#include <kdl/chaindynparam.hpp>
#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include "core/dynamics/aba.h"
#include "core/dynamics/crba.h"
#include "core/dynamics/external_force.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/rnea.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/model/configuration.h"
#include "tests/support/kdl_from_urdf.h"
#include "tests/support/kdl_convert.h"
#include "tests/support/test_models.h"
#include "tests/support/tolerances.h"

namespace igms::test {
namespace {

constexpr int kStates = 100;

class KdlChain : public ::testing::TestWithParam<NamedUrdf> {};

TEST_P(KdlChain, MatchesKdlSolvers) {
  const NamedUrdf& robot = GetParam();
  const Model model = modelFromUrdf(robot.xml);
  Data data(model);
  const KdlRobot kdl = kdlFromUrdf(robot.xml);
  ASSERT_EQ(kdl.leaves.size(), 1u);
  KDL::Chain chain;
  ASSERT_TRUE(kdl.tree.getChain(model.root_link, kdl.leaves[0], chain));
  ASSERT_EQ(static_cast<int>(chain.getNrOfJoints()), model.nv);
  const JointMap map = jointMap(model, chain);

  const KDL::Vector g(0, 0, -9.81);
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jac(chain);
  KDL::ChainIdSolver_RNE id(chain, g);
  KDL::ChainDynParam dyn(chain, g);
  KDL::ChainFdSolver_RNE fd(chain, g);

  const int n = model.nv;
  std::mt19937 rng(7);
  std::vector<Force> fext(static_cast<size_t>(model.nb));
  double worst[8] = {0};
  for (int s = 0; s < kStates; ++s) {
    const VectorX q = randomConfiguration(model, rng);
    const VectorX v = randomVector(n, rng, 2.0);
    const VectorX a = randomVector(n, rng, 5.0);
    const VectorX tau = randomVector(n, rng, 20.0);
    const KDL::JntArray kq = toKdl(q, map), kv = toKdl(v, map), ka = toKdl(a, map), ktau = toKdl(tau, map);

    // Forward kinematics of every segment (URDF link).
    forwardKinematics(model, data, q);
    std::vector<KDL::Frame> frames(chain.getNrOfSegments());
    ASSERT_GE(fk.JntToCart(kq, frames), 0);
    for (unsigned k = 0; k < chain.getNrOfSegments(); ++k) {
      const int f = model.frameIndex(chain.getSegment(k).getName());
      ASSERT_GE(f, 0);
      worst[0] = std::max(worst[0], poseError(data.oMf[static_cast<size_t>(f)], frames[k]));
    }
    // Jacobian of the tip.
    const int tip = model.frameIndex(kdl.leaves[0]);
    frameJacobian(model, data, q, tip, data.J);
    KDL::Jacobian kJ(chain.getNrOfJoints());
    ASSERT_GE(jac.JntToJac(kq, kJ), 0);
    worst[1] = std::max(worst[1], relError(fromKdl(kJ.data, map), data.J));

    // External point forces on two links, as KDL segment wrenches.
    clearExternalForces(fext);
    KDL::Wrenches wrenches(chain.getNrOfSegments(), KDL::Wrench::Zero());
    for (int e = 0; e < 2; ++e) {
      const unsigned seg = static_cast<unsigned>(rng() % chain.getNrOfSegments());
      const PointForce pf{model.frameIndex(chain.getSegment(seg).getName()), randomVector(3, rng, 0.3),
                          randomVector(3, rng, 20.0)};
      addPointForce(model, data, pf, fext);
      wrenches[seg] = wrenches[seg] + wrenchOnSegment(frames[seg], pf.point, pf.force);
    }
    // Inverse dynamics with external forces.
    KDL::JntArray ktau_id(chain.getNrOfJoints());
    ASSERT_GE(id.CartToJnt(kq, kv, ka, wrenches, ktau_id), 0);
    worst[2] = std::max(worst[2], relError(rnea(model, data, q, v, a, &fext), fromKdl(ktau_id, map)));

    // H, C v, G.
    KDL::JntSpaceInertiaMatrix kH(chain.getNrOfJoints());
    KDL::JntArray kC(chain.getNrOfJoints()), kG(chain.getNrOfJoints());
    ASSERT_GE(dyn.JntToMass(kq, kH), 0);
    ASSERT_GE(dyn.JntToCoriolis(kq, kv, kC), 0);
    ASSERT_GE(dyn.JntToGravity(kq, kG), 0);
    worst[3] = std::max(worst[3], relError(crba(model, data, q).dense(), fromKdl(kH.data, map, map)));
    const VectorX G = bias(model, data, q, VectorX::Zero(n));
    const VectorX Cv = bias(model, data, q, v) - G;
    worst[4] = std::max(worst[4], relError(G, fromKdl(kG, map)));
    worst[5] = std::max(worst[5], relError(Cv, fromKdl(kC, map)));

    // Forward dynamics with external forces: LDL^T path and ABA.
    KDL::JntArray kqdd(chain.getNrOfJoints());
    ASSERT_GE(fd.CartToJnt(kq, kv, ktau, wrenches, kqdd), 0);
    ASSERT_TRUE(forwardDynamics(model, data, q, v, tau, &fext));
    worst[6] = std::max(worst[6], relError(data.qdd, fromKdl(kqdd, map)));
    ASSERT_TRUE(aba(model, data, q, v, tau, &fext));
    worst[7] = std::max(worst[7], relError(data.qdd, fromKdl(kqdd, map)));
  }
  const char* what[8] = {"fk", "jacobian", "rnea+fext", "H", "G", "Cv", "fd+fext", "aba+fext"};
  for (int k = 0; k < 8; ++k) EXPECT_LE(worst[k], kCrossCheckRel) << robot.name << ": " << what[k];
}

INSTANTIATE_TEST_SUITE_P(Robots, KdlChain, ::testing::ValuesIn(serialRobots(20)),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace igms::test
