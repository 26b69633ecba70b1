// The paper's experiments (section V), in-process and deterministic (the
// client's logic driving the server's step in lockstep): the nominal
// straight line makes link 2 hit the obstacle; two pushes on link 2, or one
// pull of the end-effector, avoid it and reach the wall; the pull needs more
// force than the push; and the edited trajectory, saved and loaded as the
// nominal one, reaches the wall without collision and without interaction.
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/support/test_models.h"
#include "tools/scenario/scenario_run.h"

namespace igms::test {
namespace {

Scene obstacleScene() { return loadScene(sourceDir() + "/scenes/puma_obstacle.yaml"); }
std::string script(const char* name) { return sourceDir() + "/scenes/" + name; }

TEST(PaperExperiments, NominalStraightLineMakesLink2HitTheObstacle) {
  const ScenarioResult r = runScenario(obstacleScene(), "", 7.0);
  EXPECT_GT(r.collision_steps, 100);
  EXPECT_EQ(r.first_collision_what, "link2 hits obstacle");
  EXPECT_GT(r.first_collision, 1.0);
  EXPECT_GT(r.reached_wall_time, 0.0) << "it reaches the wall, through the obstacle";
}

TEST(PaperExperiments, TwoPushesOnLink2AvoidTheObstacleAndReachTheWall) {
  const ScenarioResult r = runScenario(obstacleScene(), script("paper_push.yaml"), 7.0);
  EXPECT_FALSE(r.diverged);
  EXPECT_EQ(r.collision_steps_all, 0) << "first collision at " << r.first_collision << ": " << r.first_collision_what;
  EXPECT_GT(r.min_distance_excluding_goal, 0.05);
  EXPECT_GT(r.reached_wall_time, 0.0);
  ASSERT_EQ(r.interactions.size(), 2u) << "pushing1 and pushing2";
  EXPECT_EQ(r.interaction_modes[0], 1);
  EXPECT_EQ(r.interaction_modes[1], 1);
  std::printf("push: reached the wall at %.3f s, largest force %.2f N, clearance %.3f m\n", r.reached_wall_time,
              r.max_robot_force, r.min_distance_excluding_goal);
}

TEST(PaperExperiments, PullingTheEndEffectorAvoidsTheObstacleWithMoreForceThanPushing) {
  const ScenarioResult pull = runScenario(obstacleScene(), script("paper_pull.yaml"), 7.0);
  const ScenarioResult push = runScenario(obstacleScene(), script("paper_push.yaml"), 7.0);
  EXPECT_EQ(pull.collision_steps_all, 0) << pull.first_collision_what;
  EXPECT_GT(pull.reached_wall_time, 0.0);
  ASSERT_GE(pull.interactions.size(), 1u);
  EXPECT_EQ(pull.interaction_modes[0], 2);
  EXPECT_GT(pull.max_user_force, 2.0 * push.max_user_force) << "the paper: dragging needs more force than pushing";
  std::printf("pull: reached the wall at %.3f s, largest force %.2f N (push %.2f N)\n", pull.reached_wall_time,
              pull.max_user_force, push.max_user_force);
}

TEST(PaperExperiments, TheSavedEditReplaysWithoutCollisionOrInteraction) {
  for (const char* name : {"paper_push.yaml", "paper_pull.yaml"}) {
    const std::string edited = ::testing::TempDir() + "/edited_" + name;
    runScenario(obstacleScene(), script(name), 7.0, edited);
    Scene replay = obstacleScene();
    replay.robots[0].trajectory =
        parseScene("robot: {model: x}\ntrajectory: {kind: file, file: " + edited + "}\n", "t.yaml", "").robots[0].trajectory;
    const ScenarioResult r = runScenario(replay, "", 7.5);
    EXPECT_EQ(r.collision_steps_all, 0) << name << ": " << r.first_collision_what << " at " << r.first_collision;
    EXPECT_LE((r.final_ee - Vector3(0.45, 0.47, 0.25)).norm(), 0.01) << name << ": the edit reaches the wall";
    std::remove(edited.c_str());
  }
}

}  // namespace
}  // namespace igms::test
