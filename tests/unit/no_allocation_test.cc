// After Data is built, no algorithm touches the heap (malloc is counted).
#include <gtest/gtest.h>

#include "core/dynamics/aba.h"
#include "core/dynamics/crba.h"
#include "core/dynamics/external_force.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/joint_damping.h"
#include "core/dynamics/rnea.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/model/configuration.h"
#include "tests/support/malloc_counter.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

class NoAllocation : public ::testing::TestWithParam<std::pair<std::string, bool>> {};

TEST_P(NoAllocation, AlgorithmsDoNotAllocateAfterDataIsBuilt) {
  const Model model = modelFromUrdf(readFile(sourceDir() + "/models/" + GetParam().first), GetParam().second);
  Data data(model);
  std::mt19937 rng(1);
  const VectorX q = randomConfiguration(model, rng), v = randomVector(model.nv, rng);
  const VectorX a = randomVector(model.nv, rng), tau0 = randomVector(model.nv, rng);
  VectorX tau = tau0, q_next = q;
  std::vector<Force> fext(static_cast<size_t>(model.nb));
  const int frame = static_cast<int>(model.frames.size()) - 1;
  auto all = [&] {
    forwardKinematics(model, data, q);
    clearExternalForces(fext);
    addPointForce(model, data, PointForce{frame, Vector3(0.01, 0.02, 0.03), Vector3(1, 2, 3)}, fext);
    rnea(model, data, q, v, a, &fext);
    bias(model, data, q, v);
    crba(model, data, q);
    tau = tau0;
    addJointDamping(model, v, tau);
    EXPECT_TRUE(forwardDynamics(model, data, q, v, tau, &fext));
    EXPECT_TRUE(aba(model, data, q, v, tau, &fext));
    frameJacobian(model, data, q, frame, data.J);
    pointJacobian(model, data, frame, Vector3(0.1, 0, 0), data.J);
    pointBiasAcceleration(model, data, q, v, frame, Vector3(0.1, 0, 0));
    integrateConfiguration(model, q, v, 1e-3, q_next);
  };
  all();  // warm
  EXPECT_EQ(allocationsDuring(all), 0u);
  // The counter itself works.
  EXPECT_GT(allocationsDuring([] { std::vector<double> x(100); x[0] = 1; }), 0u);
}

INSTANTIATE_TEST_SUITE_P(Models, NoAllocation,
                         ::testing::Values(std::make_pair(std::string("puma560.urdf"), false),
                                           std::make_pair(std::string("arm7.urdf"), false),
                                           std::make_pair(std::string("quadruped.urdf"), true)));

}  // namespace
}  // namespace igms::test
