// The client's predict policy against the simulation itself: from a state of
// some age, q + v h + qdd h^2 / 2 and forward kinematics must land far nearer
// the robot's true links h later than holding the old state does, on a fixed
// arm following its trajectory (PUMA) and a tumbling floating-base quadruped;
// exact at h = 0; never further ahead than its bound. And the per-cycle bound
// on the rendered force, whatever the path.
#include <gtest/gtest.h>

#include <cstdio>

#include "core/kinematics/forward_kinematics.h"
#include "core/simulation/simulation.h"
#include "haptic_client/servo/client_interaction.h"
#include "haptic_client/servo/state_estimate.h"
#include "tests/support/robot_samples.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

// The quadruped tumbling in zero gravity with its legs free (the scene as it was before it stood on
// the ground): a floating base that rotates fast.
Scene tumblingQuadruped() {
  Scene s = loadScene(test::sourceDir() + "/scenes/quadruped_float.yaml");
  s.gravity = Vector3::Zero();
  s.ground.enabled = false;
  RobotSpec& r = s.robots[0];
  r.controller = ControllerKind::ComputedTorque;  // no trajectory: passive
  r.q0.resize(19);
  r.q0 << 0, 0, 0.5, 1, 0, 0, 0, 0.1, 0.6, -1.2, -0.1, 0.6, -1.2, 0.1, 0.6, -1.2, -0.1, 0.6, -1.2;
  r.v0 = VectorX::Zero(18);
  r.v0.head<6>() << 0.1, 0, 0, 0.3, 0.5, 0.1;
  return s;
}

Scene sceneNamed(const std::string& name) {
  return name == "tumbling quadruped" ? tumblingQuadruped() : loadScene(test::sourceDir() + "/scenes/" + name);
}

TEST(StatePrediction, PredictLandsNearTheTrueStateWhereHoldDoesNot) {
  for (const char* scene : {"puma_obstacle.yaml", "tumbling quadruped"}) {
    Simulation sim(sceneNamed(scene));
    for (int k = 0; k < 500; ++k) ASSERT_TRUE(sim.step(nullptr));
    const RobotSample old = test::sampleOf(sim, 500);
    StateEstimate predict(sim.model(), FallbackPolicy::Predict, 0.1);
    predict.offer(old, 0.0);
    std::vector<SE3> links(sim.model().frames.size());
    bool fallback = false;
    ASSERT_TRUE(predict.estimate(old.sim_time, links, &fallback));
    EXPECT_FALSE(fallback);
    EXPECT_EQ(test::worstLinkError(links, old.links), 0.0) << scene << ": a state of age 0 is used as it is";
    int stepped = 0;
    for (int h_ms : {5, 20, 50}) {
      for (; stepped < h_ms; ++stepped) ASSERT_TRUE(sim.step(nullptr));
      const RobotSample truth = test::sampleOf(sim, 500 + h_ms);
      ASSERT_TRUE(predict.estimate(truth.sim_time, links, &fallback));
      EXPECT_TRUE(fallback);
      const double e_predict = test::worstLinkError(links, truth.links);
      const double e_hold = test::worstLinkError(old.links, truth.links);
      std::printf("%-22s %2d ms ahead: predict %.3f mm, hold %.3f mm off the true links\n", scene, h_ms,
                  e_predict * 1e3, e_hold * 1e3);
      EXPECT_GT(e_hold, 1e-4) << scene << ": the robot moves (else the test shows nothing)";
      EXPECT_LT(e_predict, 0.02 * e_hold) << scene << " at " << h_ms << " ms";
    }
  }
}

TEST(StatePrediction, NeverFurtherAheadThanItsBound) {
  Simulation sim(tumblingQuadruped());
  for (int k = 0; k < 100; ++k) ASSERT_TRUE(sim.step(nullptr));
  StateEstimate e(sim.model(), FallbackPolicy::Predict, 0.02);
  e.offer(test::sampleOf(sim, 1), 0.0);
  std::vector<SE3> at_bound(sim.model().frames.size()), beyond(sim.model().frames.size());
  e.estimate(sim.time() + 0.02, at_bound, nullptr);
  e.estimate(sim.time() + 5.0, beyond, nullptr);
  EXPECT_EQ(test::worstLinkError(at_bound, beyond), 0.0) << "a 5 s old state is predicted 20 ms ahead, no further";
}

TEST(StatePrediction, HoldNeedsNoModelButPredictDoes) {
  EXPECT_THROW(StateEstimate(1, 1, FallbackPolicy::Predict), std::invalid_argument);
  FallbackPolicy p;
  ASSERT_TRUE(parseFallback("predict", &p));
  EXPECT_EQ(p, FallbackPolicy::Predict);
  EXPECT_STREQ(fallbackName(p), "predict");
}

// Whatever the target does (a jump to 30 N, a reversal, a loss ramp, a resync),
// the rendered force moves by at most the bound a cycle, and each cut is counted.
TEST(ForceBound, TheRenderedForceChangesByAtMostTheBoundEachCycle) {
  const ResolvedScene scene = resolveScene(loadScene(test::sourceDir() + "/scenes/puma_obstacle.yaml"));
  ClientInteraction c(scene);
  c.render(Vector3::Zero(), Vector3::Zero(), false, false, 0.001, RenderLimits{30.0, 1.0, false});  // arms the start-up guard
  Vector3 last = Vector3::Zero();
  double worst = 0.0;
  const Vector3 targets[] = {Vector3(30, 0, 0), Vector3(-30, 0, 0), Vector3(0, 0, 0), Vector3(0, 25, 5)};
  int cycles = 0;
  for (const Vector3& target : targets)
    for (int k = 0; k < 80; ++k, ++cycles) {
      const Vector3 f = c.render(target, Vector3::Zero(), k > 60, k == 30, 0.001, RenderLimits{30.0, 1.0, false});
      worst = std::max(worst, (f - last).norm());
      last = f;
    }
  EXPECT_LE(worst, 1.0 + 1e-12);
  EXPECT_NEAR(c.maxForceStep(), worst, 1e-12);
  EXPECT_GT(c.slewLimited(), 60) << "the jumps to 30 N and the reversal were cut";
  EXPECT_LT(c.slewLimited(), cycles);
  // A force within the bound of the last passes unchanged.
  ClientInteraction d(scene);
  d.render(Vector3::Zero(), Vector3::Zero(), false, false, 0.001, RenderLimits{30.0, 1.0, false});
  EXPECT_TRUE(d.render(Vector3(0.4, 0, 0), Vector3::Zero(), false, false, 0.001, RenderLimits{30.0, 1.0, false})
                  .isApprox(Vector3(0.4, 0, 0)));
  EXPECT_EQ(d.slewLimited(), 0);
}

}  // namespace
}  // namespace igms
