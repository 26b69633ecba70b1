// Commands applied between steps (server/loop/command_handler): validation,
// and that a rejected command changes nothing.
#include <gtest/gtest.h>

#include "server/loop/command_handler.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

Simulation wallScene() { return Simulation(loadScene(sourceDir() + "/scenes/puma_wall.yaml")); }

command_t command(int8_t kind) {
  command_t c{};
  c.kind = kind;
  return c;
}

TEST(CommandHandler, PauseStartAndStepSetTheLoopControl) {
  Simulation sim = wallScene();
  LoopControl control;
  EXPECT_TRUE(applyCommand(command(command_t::PAUSE), sim, control).accepted);
  EXPECT_TRUE(control.paused);
  EXPECT_TRUE(applyCommand(command(command_t::STEP), sim, control).accepted);
  EXPECT_TRUE(applyCommand(command(command_t::STEP), sim, control).accepted);
  EXPECT_EQ(control.steps_requested, 2);
  EXPECT_TRUE(applyCommand(command(command_t::START), sim, control).accepted);
  EXPECT_FALSE(control.paused);
  EXPECT_TRUE(applyCommand(command(command_t::SHUTDOWN), sim, control).accepted);
  EXPECT_FALSE(control.running);
}

TEST(CommandHandler, AFailedSetTrajectoryLeavesAPausedServerPausedAndTheTrajectoryAlone) {
  Simulation sim = wallScene();
  LoopControl control;
  control.paused = true;
  const VectorX goal = sim.robot(0).goal();
  command_t c = command(command_t::SET_TRAJECTORY);
  c.trajectory.t = {0.0, 1.0};
  c.trajectory.q = {std::vector<double>(6, 0.0), std::vector<double>(5, 0.0)};  // a point of the wrong size
  const CommandResult r = applyCommand(c, sim, control);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.message.find("coordinates"), std::string::npos) << r.message;
  EXPECT_TRUE(control.paused);
  EXPECT_EQ(sim.robot(0).goal(), goal);
  c.trajectory.q[1] = std::vector<double>(6, 0.1);
  EXPECT_TRUE(applyCommand(c, sim, control).accepted);
  EXPECT_TRUE(control.paused);
  EXPECT_TRUE(sim.robot(0).goal().isApprox(VectorX::Constant(6, 0.1), 1e-12));
}

// In a scene of several robots a trajectory goes to the robot its text names, in that robot's own
// coordinates; the others keep theirs.
TEST(CommandHandler, SetTrajectoryGoesToTheRobotItNames) {
  Simulation sim(loadScene(sourceDir() + "/scenes/workcell.yaml"));
  LoopControl control;
  ASSERT_EQ(sim.robots(), 2);
  const VectorX puma_goal = sim.robot(0).goal();
  const int go1_nq = sim.robot(1).part().nq();
  command_t c = command(command_t::SET_TRAJECTORY);
  c.text = "go1";
  c.trajectory.t = {0.0, 1.0};
  c.trajectory.q = {std::vector<double>(sim.model().nq, 0.0), std::vector<double>(sim.model().nq, 0.0)};
  CommandResult r = applyCommand(c, sim, control);
  EXPECT_FALSE(r.accepted) << "the environment's coordinates are not the Go1's";
  EXPECT_NE(r.message.find("the robot " + std::to_string(go1_nq)), std::string::npos) << r.message;
  VectorX stance = sim.robot(1).goal();
  c.trajectory.q = {std::vector<double>(stance.data(), stance.data() + go1_nq),
                    std::vector<double>(stance.data(), stance.data() + go1_nq)};
  c.trajectory.q[1][go1_nq - 1] += 0.1;  // its last joint a little further
  r = applyCommand(c, sim, control);
  EXPECT_TRUE(r.accepted) << r.message;
  stance[go1_nq - 1] += 0.1;
  EXPECT_EQ(sim.robot(1).goal(), stance);
  EXPECT_EQ(sim.robot(0).goal(), puma_goal) << "the PUMA keeps its own";
  c.text = "ur5";
  r = applyCommand(c, sim, control);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.message.find("no robot named 'ur5'"), std::string::npos) << r.message;
}

TEST(CommandHandler, UnknownKindsAndInvalidArgumentsAreRejectedWithAReason) {
  Simulation sim = wallScene();
  LoopControl control;
  EXPECT_FALSE(applyCommand(command(77), sim, control).accepted);
  command_t gains = command(command_t::SET_GAINS);
  gains.nvalues = 3;
  gains.values = {2000.0, NAN, 10.0};
  EXPECT_FALSE(applyCommand(gains, sim, control).accepted);
  gains.nvalues = 2;
  gains.values = {2000.0, 800.0};
  EXPECT_FALSE(applyCommand(gains, sim, control).accepted);
  gains.nvalues = 5;
  gains.values = {2000.0, 800.0, 10.0, -1.0, 0.5};
  EXPECT_FALSE(applyCommand(gains, sim, control).accepted) << "a negative k_rot";
  gains.values = {2000.0, 800.0, 10.0, 30.0, 0.5};
  EXPECT_TRUE(applyCommand(gains, sim, control).accepted) << "the 6-D pull's gains too";
  // The push coupling's damper (puma_wall's default, 0.01 s x 2000 = 20 N s/m) keeps k_p up to 2 b / T = 40000.
  gains.nvalues = 3;
  gains.values = {40000.0, 800.0, 10.0};
  EXPECT_TRUE(applyCommand(gains, sim, control).accepted);
  gains.values = {40001.0, 800.0, 10.0};
  const CommandResult stiff = applyCommand(gains, sim, control);
  EXPECT_FALSE(stiff.accepted);
  EXPECT_NE(stiff.message.find("would not be passive"), std::string::npos) << stiff.message;
  EXPECT_FALSE(applyCommand(command(command_t::LOAD_SCENE), sim, control).accepted) << "no file";
  EXPECT_FALSE(control.reload);
  EXPECT_TRUE(control.running);
  command_t save = command(command_t::SAVE_TRAJECTORY);
  save.text = "/nonexistent-dir/x.yaml";
  const CommandResult r = applyCommand(save, sim, control);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.message.find("/nonexistent-dir/x.yaml"), std::string::npos) << r.message;
}

TEST(CommandHandler, ResetAsksForANewSessionAndLoadSceneEndsThisOne) {
  Simulation sim = wallScene();
  LoopControl control;
  for (int k = 0; k < 100; ++k) sim.step(nullptr);
  EXPECT_TRUE(applyCommand(command(command_t::RESET), sim, control).accepted);
  EXPECT_TRUE(control.new_session);
  EXPECT_EQ(sim.steps(), 0);
  command_t load = command(command_t::LOAD_SCENE);
  load.text = "scenes/puma_swing.yaml";
  EXPECT_TRUE(applyCommand(load, sim, control).accepted);
  EXPECT_TRUE(control.reload);
  EXPECT_FALSE(control.running);
  EXPECT_EQ(control.scene_path, "scenes/puma_swing.yaml");
}

}  // namespace
}  // namespace igms::test
