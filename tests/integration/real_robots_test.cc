// Robots as users have them (example-robot-data, scripts/setup/fetch_robots.sh),
// in-process and deterministic (the client's logic driving the server's step
// in lockstep): a push on a collision mesh moves the touched link off its
// nominal path, a pull drags the end-effector toward the device. Skipped when
// the models were not fetched.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>

#include "core/kinematics/forward_kinematics.h"
#include "core/scene/resolved_scene.h"
#include "tests/support/test_models.h"
#include "tools/scenario/scenario_run.h"

namespace igms::test {
namespace {

bool fetched() {
  return std::filesystem::exists(sourceDir() + "/third_party/example-robot-data/robots/panda_description");
}

// The largest distance between a link's positions in two runs at the same steps.
double largestOffPath(const Model& m, const ScenarioResult& a, const ScenarioResult& b, const std::string& link) {
  Data da(m), db(m);
  const int f = m.frameIndex(link);
  double worst = 0.0;
  for (size_t k = 0; k < std::min(a.samples.size(), b.samples.size()); ++k) {
    forwardKinematics(m, da, Eigen::Map<const VectorX>(a.samples[k].q.data(), m.nq));
    forwardKinematics(m, db, Eigen::Map<const VectorX>(b.samples[k].q.data(), m.nq));
    worst = std::max(worst, (framePose(m, da, f).p - framePose(m, db, f).p).norm());
  }
  return worst;
}

struct Case {
  const char* scene;
  const char* push_script;
  const char* pushed_link;
  const char* pull_script;
};

class RealRobot : public ::testing::TestWithParam<Case> {};

TEST_P(RealRobot, PushMovesTheTouchedMeshLinkAndPullDragsTheHand) {
  if (!fetched()) GTEST_SKIP() << "example-robot-data not fetched (scripts/setup/fetch_robots.sh)";
  const Case& c = GetParam();
  const Scene scene = loadScene(sourceDir() + "/scenes/" + c.scene);
  const ResolvedScene resolved = resolveScene(scene);
  const Model& m = *resolved.model;
  const double seconds = 4.0;
  const ScenarioResult nominal = runScenario(scene, "", seconds);
  ASSERT_FALSE(nominal.diverged);
  const ScenarioResult push = runScenario(scene, sourceDir() + "/scenes/" + c.push_script, seconds);
  ASSERT_FALSE(push.diverged);
  ASSERT_FALSE(push.interaction_modes.empty()) << c.scene << ": the scripted tip touched nothing";
  EXPECT_EQ(push.interaction_modes[0], 1) << "a push";
  EXPECT_GT(push.max_robot_force, 1.0);
  const double off = largestOffPath(m, push, nominal, c.pushed_link);
  EXPECT_GT(off, 0.01) << c.pushed_link << " moved off its nominal path";
  std::printf("%s: push on %s, largest force %.1f N, the link %.3f m off its nominal path\n", c.scene, c.pushed_link,
              push.max_robot_force, off);
  if (!c.pull_script) return;
  const ScenarioResult pull = runScenario(scene, sourceDir() + "/scenes/" + c.pull_script, seconds);
  ASSERT_FALSE(pull.diverged);
  ASSERT_FALSE(pull.interaction_modes.empty());
  EXPECT_EQ(pull.interaction_modes[0], 2) << "a pull";
  // Toward the device: the end-effector ends nearer the pull's target than the nominal run's.
  const size_t k = std::min(pull.samples.size(), nominal.samples.size()) / 2;  // mid-pull
  const Vector3 moved = pull.samples[k].ee - nominal.samples[k].ee;
  EXPECT_GT(moved.norm(), 0.02) << "the pull dragged the end-effector";
  std::printf("%s: pull, largest force %.1f N, the end-effector %.3f m from its nominal position at t = %.2f s\n",
              c.scene, pull.max_robot_force, moved.norm(), pull.samples[k].t);
}

INSTANTIATE_TEST_SUITE_P(ExampleRobotData, RealRobot,
                         ::testing::Values(Case{"panda_obstacle.yaml", "panda_push.yaml", "panda_link4",
                                                "panda_pull.yaml"},
                                           Case{"ur5_line.yaml", "ur5_push.yaml", "forearm_link", nullptr},
                                           Case{"solo12_float.yaml", "solo12_push.yaml", "base_link", nullptr}),
                         [](const auto& info) {
                           std::string n = info.param.scene;
                           return n.substr(0, n.find('_'));
                         });

}  // namespace
}  // namespace igms::test
