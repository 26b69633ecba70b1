// The hand in the environment: a scripted probe pushes a box across the table
// of scenes/puma_table.yaml and then goes 10 cm into the solid table (its proxy
// stays on the top face, the force steps stay within the device's 1 N a
// cycle); the pull lifts a free box and drops it, and it settles on the table;
// with two robots, a hand holds only the robot it acts on.
#include <gtest/gtest.h>

#include "core/model/environment_model.h"
#include "core/simulation/simulation.h"
#include "tests/support/test_models.h"
#include "tools/scenario/scenario_run.h"

namespace igms {
namespace {

Scene shipped(const std::string& name) { return loadScene(test::sourceDir() + "/scenes/" + name); }

// A coordinate of q by its column name (coordinateNames).
double column(const ScenarioResult& r, const std::string& name) {
  for (size_t c = 0; c < r.q_columns.size(); ++c)
    if (r.q_columns[c] == name) return r.samples.back().q[c];
  ADD_FAILURE() << "no column " << name;
  return 0.0;
}

TEST(HandInEnvironment, AProbePushesABoxAcrossTheTableAndFeelsTheTableAsAWall) {
  const ScenarioResult r = runScenario(shipped("puma_table.yaml"), test::sourceDir() + "/scenes/table_box_push.yaml",
                                       6.0, "", 0.01, true);
  ASSERT_FALSE(r.diverged);
  const double x = column(r, "box_b.x"), z = column(r, "box_b.z");
  std::printf("box_b moved %.1f mm along x (script: the tip from 0.36 to 0.46 m), ends at z %.5f; proxy overlap "
              "%.2g m with the device %.3f m behind it; largest force step %.3f N\n",
              (x - 0.42) * 1e3, z, r.max_proxy_penetration, r.max_device_behind_proxy, r.max_force_step);
  EXPECT_GT(x - 0.42, 0.07) << "pushed by the script's intent";
  EXPECT_LT(x - 0.42, 0.13);
  EXPECT_NEAR(z, 0.16, 2e-3) << "it ends resting on the table top";
  EXPECT_LT(x + 0.04, 0.6) << "wholly on the table";
  EXPECT_GE(r.max_device_behind_proxy, 0.099) << "the device went 10 cm into the table";
  EXPECT_LE(r.max_proxy_penetration, 1e-3) << "the proxy stayed on the surface";
  EXPECT_LE(r.max_force_step, 1.0 + 1e-12) << "the hand's force moves by 1 N a cycle at most";
  EXPECT_GT(r.max_user_force, 3.0) << "the table is felt as a wall (the device's 3.3 N)";
  EXPECT_GT(r.max_robot_force, 0.5) << "the push acted on the box";
}

// A scripted hand names the body it pulls (scenes/ball_lift.yaml: the press attaches to the ball).
TEST(HandInEnvironment, AScriptedPullNamesTheBallItLifts) {
  const ScenarioResult r = runScenario(shipped("hand_table.yaml"), test::sourceDir() + "/scenes/ball_lift.yaml", 4.0,
                                       "", 0.01, true);
  ASSERT_FALSE(r.diverged);
  double highest = 0.0;
  size_t z = 0;
  for (size_t c = 0; c < r.q_columns.size(); ++c)
    if (r.q_columns[c] == "ball.z") z = c;
  ASSERT_GT(z, 0u);
  for (const auto& s : r.samples) highest = std::max(highest, s.q[z]);
  std::printf("the ball rose to z %.4f m (from 0.16) and ends at %.5f m; largest force step %.3f N\n", highest,
              column(r, "ball.z"), r.max_force_step);
  EXPECT_GT(highest, 0.16 + 0.07) << "lifted by most of the script's 10 cm";
  EXPECT_NEAR(column(r, "ball.z"), 0.16, 1e-3) << "let go, it fell back onto the table and rests there";
  EXPECT_NEAR(column(r, "box_a.x"), 0.42, 1e-6) << "nothing else was pulled";
  EXPECT_LE(r.max_force_step, 1.0 + 1e-12);
}

// The demo's environment run (scenes/table_clear.yaml): without a hand the arm sweeps box_b along its
// line; scenes/table_clear_push.yaml pushes it out of the way first, and the arm passes clear of it.
TEST(HandInEnvironment, AHandClearsTheArmsWayBeforeItArrives) {
  const ScenarioResult nominal = runScenario(shipped("table_clear.yaml"), "", 6.0, "", 0.01, false);
  const ScenarioResult r = runScenario(shipped("table_clear.yaml"), test::sourceDir() + "/scenes/table_clear_push.yaml",
                                       6.0, "", 0.01, true);
  ASSERT_FALSE(nominal.diverged);
  ASSERT_FALSE(r.diverged);
  std::printf("box_b without a hand ends at (%.3f, %.3f); pushed first, at (%.3f, %.3f, %.4f); the wall reached at "
              "%.3f s; largest force step %.3f N\n",
              column(nominal, "box_b.x"), column(nominal, "box_b.y"), column(r, "box_b.x"), column(r, "box_b.y"),
              column(r, "box_b.z"), r.reached_wall_time, r.max_force_step);
  EXPECT_GT(std::abs(column(nominal, "box_b.y")), 0.1) << "without a hand the arm sweeps the box along its line";
  EXPECT_GT(column(r, "box_b.x") - 0.42, 0.09) << "the hand pushed it along +x";
  EXPECT_NEAR(column(r, "box_b.y"), 0.0, 5e-3) << "and the arm never touched it";
  EXPECT_NEAR(column(r, "box_b.z"), 0.16, 2e-3) << "it ends on the table";
  for (const char* other : {"box_a.x", "box_c.x"}) EXPECT_NEAR(column(r, other), 0.56, 1e-6) << other;
  EXPECT_GT(r.reached_wall_time, 0.0) << "the arm reached the wall";
  EXPECT_EQ(r.collision_steps, 0);
  EXPECT_LE(r.max_force_step, 1.0 + 1e-12);
}

// The demo's Go1 (scenes/go1_stand.yaml, gravity, PD legs): a hand pushes the trunk sideways; it
// gives way some millimetres, stands, and comes back when let go.
TEST(HandInEnvironment, TheGo1StandsWhileAHandPushesItsTrunk) {
  const ScenarioResult r = runScenario(shipped("go1_stand.yaml"), test::sourceDir() + "/scenes/go1_trunk_push.yaml",
                                       5.0, "", 0.01, true);
  ASSERT_FALSE(r.diverged);
  double lowest = 1.0, furthest = 0.0;
  size_t y = 0, z = 0;
  for (size_t c = 0; c < r.q_columns.size(); ++c) {
    if (r.q_columns[c] == "q1") y = c;  // the floating base: x y z first
    if (r.q_columns[c] == "q2") z = c;
  }
  ASSERT_GT(z, 0u) << "the floating base's columns";
  for (const auto& s : r.samples) {
    lowest = std::min(lowest, s.q[z]);
    furthest = std::min(furthest, s.q[y]);
  }
  std::printf("the trunk gave way %.2f mm under up to %.1f N, lowest %.4f m, ends at y %.2f mm\n", -furthest * 1e3,
              r.max_robot_force, lowest, column(r, "q1") * 1e3);
  EXPECT_GT(r.max_robot_force, 10.0) << "the push acted";
  EXPECT_LT(furthest, -0.003) << "the trunk gave way to the push";
  EXPECT_GT(lowest, 0.25) << "and the Go1 stayed standing";
  EXPECT_NEAR(column(r, "q1"), 0.0, 1e-3) << "its feet stuck: let go, it came back";
  EXPECT_LE(r.max_force_step, 1.0 + 1e-12);
}

TEST(HandInEnvironment, ThePullLiftsAFreeBoxAndDropsItAndItSettles) {
  Scene scene = shipped("puma_table.yaml");
  scene.robots.front().trajectory = TrajectorySpec{};  // the arm stands still: it would knock the box over
  Simulation sim(scene);
  const int box = sim.model().frameIndex("box_b");
  ASSERT_GE(box, 0);
  for (int k = 0; k < 100; ++k) ASSERT_TRUE(sim.step(nullptr));
  const Vector3 start = sim.linkPoses()[static_cast<size_t>(box)].p;
  InteractionInput pull;
  pull.mode = InteractionMode::Pull;
  pull.attach_frame = box;
  pull.attach_point = Vector3::Zero();
  pull.client = 1;
  int64_t seq = 1;
  for (int k = 0; k <= 1000; ++k) {  // up 10 cm over 0.5 s, then held
    pull.tip_position = start + Vector3(0, 0, 0.1 * std::min(1.0, k / 500.0));
    pull.tip_velocity = Vector3(0, 0, k < 500 ? 0.2 : 0.0);
    pull.seq = seq++;
    ASSERT_TRUE(sim.step(&pull));
  }
  const double lifted = sim.linkPoses()[static_cast<size_t>(box)].p.z();
  EXPECT_NEAR(lifted, start.z() + 0.1 - 0.3 * 9.81 / 800.0, 1e-3) << "held up, the spring stretched by m g / k";
  InteractionInput none;
  none.client = 1;
  none.tip_position = start + Vector3(0, 0, 0.3);
  for (int k = 0; k < 1500; ++k) {
    none.seq = seq++;
    ASSERT_TRUE(sim.step(&none));
  }
  const ModelPart& part = sim.model().parts[static_cast<size_t>(sim.model().partOfFrame(box))];
  const FreeBodyState s = freeBodyState(part, sim.q(), sim.v());
  EXPECT_NEAR(s.p.z(), start.z(), 1e-3) << "dropped, it fell back onto the table";
  EXPECT_LT(s.v.norm() + s.w.norm(), 1e-3) << "and came to rest";
}

TEST(HandInEnvironment, WithTwoRobotsAHandHoldsOnlyTheOneItActsOn) {
  const Scene scene = shipped("workcell.yaml");
  Simulation nominal(scene), pulled(scene);
  const int trunk = pulled.model().frameIndex("go1/trunk");
  ASSERT_GE(trunk, 0);
  const ModelPart& puma = pulled.model().parts[0];
  for (int k = 0; k < 200; ++k) {
    ASSERT_TRUE(nominal.step(nullptr));
    ASSERT_TRUE(pulled.step(nullptr));
  }
  const Vector3 at = pulled.linkPoses()[static_cast<size_t>(trunk)].p;
  InteractionInput pull;
  pull.mode = InteractionMode::Pull;
  pull.attach_frame = trunk;
  pull.client = 1;
  double puma_off = 0.0;
  for (int k = 1; k <= 1000; ++k) {  // drag the trunk 3 cm sideways
    pull.tip_position = at + Vector3(0, 0.03 * std::min(1.0, k / 300.0), 0);
    pull.seq = k;
    ASSERT_TRUE(pulled.step(&pull));
    ASSERT_TRUE(nominal.step(nullptr));
    puma_off = std::max(puma_off, (pulled.q() - nominal.q()).segment(puma.q_begin, puma.nq()).cwiseAbs().maxCoeff());
  }
  const double moved = (pulled.linkPoses()[static_cast<size_t>(trunk)].p - at).y();
  std::printf("go1 trunk dragged %.1f mm; the PUMA's joints %.2g rad off its unheld run\n", moved * 1e3, puma_off);
  EXPECT_GT(moved, 0.003) << "the pull moved the Go1 (standing on its PD legs)";
  EXPECT_LT(puma_off, 1e-6) << "the PUMA kept following its line: it was not held";
}

}  // namespace
}  // namespace igms
