// What a released tip does (haptic_client/servo/client_interaction.h): after a
// pull is let go, the hand withdraws from where it held the robot, often
// through it; the tip pushes nothing until it has been clear of every link for
// 50 cycles. A tip that was never pulling pushes at the first touch.
#include <gtest/gtest.h>

#include "core/geometry/deepest_contact.h"
#include "core/simulation/simulation.h"
#include "haptic_client/servo/client_interaction.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

struct Bench {
  ResolvedScene scene = resolveScene(loadScene(test::sourceDir() + "/scenes/puma_obstacle.yaml"));
  std::vector<SE3> links = Simulation(scene.scene).linkPoses();
  // A tip 1 mm into link 2 from above, and one 10 cm clear of it.
  Vector3 touching, clear;
  Bench() {
    const int link2 = scene.model->frameIndex("link2");
    Vector3 tip = links[static_cast<size_t>(link2)].p + Vector3(0, 0, 0.3);
    for (int k = 0; k < 6000; ++k, tip.z() -= 1e-4) {
      const LinkContact c = deepestContact(*scene.model, [&](int f) { return links[static_cast<size_t>(f)]; }, tip,
                                           scene.scene.push.tip_radius);
      if (c.contact.touching && c.contact.depth > 1e-3) break;
    }
    touching = tip;
    clear = tip + Vector3(0, 0, 0.1);
  }
  // One servo cycle: the input from the device, then the force against the robot. The mode sent.
  int8_t cycle(ClientInteraction& c, const Vector3& tip, int buttons) {
    haptic_input_t msg{};
    c.fillInput(tip, Vector3::Zero(), buttons, msg);
    c.render(c.userForce(links, 0.0, tip, Vector3::Zero()), Vector3::Zero(), false, false, 0.001,
             RenderLimits{30.0, 1.0, false});
    return msg.mode;
  }
};

TEST(ReleasedTip, PushesNothingUntilItHasBeenClearOfTheRobotFor50Cycles) {
  Bench b;
  {  // never pulled: the first touch pushes (one cycle later: the input carries the last cycle's contact)
    ClientInteraction c(b.scene);
    c.render(Vector3::Zero(), Vector3::Zero(), false, false, 0.001, RenderLimits{30.0, 1.0, false});
    b.cycle(c, b.clear, 0);
    b.cycle(c, b.touching, 0);
    EXPECT_EQ(b.cycle(c, b.touching, 0), haptic_input_t::MODE_PUSH);
  }
  ClientInteraction c(b.scene);
  c.render(Vector3::Zero(), Vector3::Zero(), false, false, 0.001, RenderLimits{30.0, 1.0, false});
  for (int k = 0; k < 20; ++k) EXPECT_EQ(b.cycle(c, b.clear, 1), haptic_input_t::MODE_PULL);
  // Let go where the tip touches the arm: nothing, however long it stays.
  for (int k = 0; k < 200; ++k) EXPECT_EQ(b.cycle(c, b.touching, 0), haptic_input_t::MODE_NONE) << k;
  // Clear for 49 cycles, then back: still nothing.
  for (int k = 0; k < 49; ++k) b.cycle(c, b.clear, 0);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(b.cycle(c, b.touching, 0), haptic_input_t::MODE_NONE) << k;
  // Clear for 50: the next touch pushes.
  for (int k = 0; k < 50; ++k) b.cycle(c, b.clear, 0);
  b.cycle(c, b.touching, 0);
  EXPECT_EQ(b.cycle(c, b.touching, 0), haptic_input_t::MODE_PUSH);
}

}  // namespace
}  // namespace igms
