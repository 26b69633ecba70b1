// What a released tip does (haptic_client/servo/client_interaction.h): after a
// pull is let go, the hand withdraws from where it held the robot, often
// through it. The tip's proxy (core/interaction/proxy.h) stays free while the
// tip's centre is inside a link: it pushes nothing until it has come out, and
// then starts at the surface. A tip that was never pulling pushes at the first touch.
#include <gtest/gtest.h>

#include <limits>

#include "core/geometry/deepest_contact.h"
#include "core/simulation/simulation.h"
#include "haptic_client/servo/client_interaction.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

struct Bench {
  ResolvedScene scene = resolveScene(loadScene(test::sourceDir() + "/scenes/puma_obstacle.yaml"));
  std::vector<SE3> links = Simulation(scene.scene).linkPoses();
  // A tip 1 mm into link 2 from above, one 5 cm clear of it, and one with its centre 2 cm inside.
  Vector3 touching, clear, inside;
  Bench() {
    const int link2 = scene.model->frameIndex("link2");
    Vector3 tip = links[static_cast<size_t>(link2)].p + Vector3(0, 0, 0.3);
    for (int k = 0; k < 6000; ++k, tip.z() -= 1e-4) {
      const LinkContact c = deepestContact(*scene.model, [&](int f) { return links[static_cast<size_t>(f)]; }, tip,
                                           scene.scene.push.tip_radius);
      if (c.contact.touching && c.contact.depth > 1e-3) break;
    }
    touching = tip;
    clear = tip + Vector3(0, 0, 0.05);
    inside = tip - Vector3(0, 0, 0.03);
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

TEST(ReleasedTip, PushesNothingUntilItsCentreHasComeOutOfTheLink) {
  Bench b;
  {  // never pulled: the first touch pushes (one cycle later: the input carries the last cycle's contact)
    ClientInteraction c(b.scene);
    c.render(Vector3::Zero(), Vector3::Zero(), false, false, 0.001, RenderLimits{30.0, 1.0, false});
    b.cycle(c, b.clear, 0);
    b.cycle(c, b.touching, 0);
    EXPECT_EQ(b.cycle(c, b.touching, 0), haptic_input_t::MODE_PUSH);
    EXPECT_GT(c.userForce(b.links, 0.0, b.touching, Vector3::Zero()).z(), 0.0) << "the link pushes the hand up";
  }
  ClientInteraction c(b.scene);
  c.render(Vector3::Zero(), Vector3::Zero(), false, false, 0.001, RenderLimits{30.0, 1.0, false});
  for (int k = 0; k < 20; ++k) EXPECT_EQ(b.cycle(c, b.inside, 1), haptic_input_t::MODE_PULL);
  // Let go with the tip's centre inside the arm: nothing, however long it stays, and no force.
  for (int k = 0; k < 200; ++k) EXPECT_EQ(b.cycle(c, b.inside, 0), haptic_input_t::MODE_NONE) << k;
  EXPECT_EQ(c.userForce(b.links, 0.0, b.inside, Vector3::Zero()), Vector3::Zero());
  EXPECT_TRUE(c.proxy().free());
  // Out to the surface: the proxy engages there, and the next touch pushes.
  b.cycle(c, b.touching, 0);
  EXPECT_FALSE(c.proxy().free());
  EXPECT_EQ(b.cycle(c, b.touching, 0), haptic_input_t::MODE_PUSH);
  // Back in, 3 cm: the proxy stays on the surface and the force grows, along the same side.
  for (int k = 0; k < 5; ++k) b.cycle(c, b.inside, 0);
  EXPECT_EQ(b.cycle(c, b.inside, 0), haptic_input_t::MODE_PUSH);
  const Vector3 f = c.userForce(b.links, 0.0, b.inside, Vector3::Zero());
  EXPECT_GT(f.z(), 0.9 * std::min(b.scene.scene.push.max_force, b.scene.scene.push.k_p * 0.031)) << f.transpose();
}

// The 6-D pull on the client's side: the grab leaves the rotational spring
// relaxed, a turn of the device gives the server's law's torque (against the
// estimate), and what reaches the hand is clamped to the device's torque and
// bounded per cycle.
TEST(SixDofPull, TheGrabIsRelaxedAndATurnGivesTheServersTorque) {
  Bench b;
  ClientInteraction c(b.scene);
  c.render(Vector3::Zero(), Vector3::Zero(), false, false, 0.001, RenderLimits{30.0, 1.0, false});
  const int ee = b.scene.model->frameIndex("ee_link");
  const Vector3 x = b.links[static_cast<size_t>(ee)].p;
  const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.7, Vector3(1, 1, 0).normalized()));  // any device orientation
  auto cycle = [&](const Eigen::Quaterniond& q, int buttons) {
    haptic_input_t msg{};
    c.setOrientation(true, q, Vector3::Zero());
    c.fillInput(x, Vector3::Zero(), buttons, msg);
    c.userForce(b.links, 0.0, x, Vector3::Zero());
    return msg;
  };
  cycle(q0, 0);
  const haptic_input_t grab = cycle(q0, 1);
  EXPECT_TRUE(grab.has_orientation);
  EXPECT_LE(c.userTorque().norm(), 1e-9) << "the grab leaves the rotational spring relaxed";
  // The server's law on the message: R_link * attach = R_tip at the grab.
  const Eigen::Quaterniond attach(grab.attach_orientation[0], grab.attach_orientation[1], grab.attach_orientation[2],
                                  grab.attach_orientation[3]);
  const Matrix3 grasped = b.links[static_cast<size_t>(ee)].R * attach.toRotationMatrix();
  EXPECT_LE((grasped - q0.toRotationMatrix()).norm(), 1e-9);
  // Turn the device 0.1 rad about x (world): the hand feels -k_rot * 0.1 about x.
  const Eigen::Quaterniond turned = Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Vector3::UnitX())) * q0;
  cycle(turned, 1);
  const double k_rot = b.scene.scene.pull.k_rot;
  ASSERT_GT(k_rot, 0.0);
  EXPECT_LE((c.userTorque() - (-k_rot * 0.1) * Vector3::UnitX()).norm(), 1e-9) << c.userTorque().transpose();
  // Rendered: at most 0.5 N m (the device's), moving by at most 0.02 N m a cycle.
  Vector3 last = Vector3::Zero();
  double biggest_step = 0.0;
  Vector3 rendered;
  for (int k = 0; k < 200; ++k) {
    rendered = c.renderTorque(c.userTorque(), 0.001, 0.5, 0.02, false);
    biggest_step = std::max(biggest_step, (rendered - last).norm());
    last = rendered;
  }
  EXPECT_NEAR(rendered.norm(), std::min(0.5, k_rot * 0.1), 1e-9);
  EXPECT_LE(biggest_step, 0.02 + 1e-12);
  EXPECT_EQ(c.renderTorque(c.userTorque(), 0.001, 0.0, 0.02, false), Vector3::Zero()) << "a 3-dof device: none";
  // A 3-D pull scene ignores the orientation.
  Scene s = b.scene.scene;
  s.pull.k_rot = 0.0;
  ClientInteraction c3(resolveScene(s));
  haptic_input_t msg{};
  c3.setOrientation(true, q0, Vector3::Zero());
  c3.fillInput(x, Vector3::Zero(), 1, msg);
  EXPECT_FALSE(msg.has_orientation);
}

// A device's stable stiffness (DeviceLimits::max_stiffness) scales what the hand feels: the
// paper's scene is max(k_p 2000, k 800) N/m x workspace scale 4 = 8000 N/m at the device.
TEST(DeviceStiffness, ScalesTheForceTheHandFeelsNotTheRobots) {
  Bench b;
  EXPECT_DOUBLE_EQ(couplingStiffness(b.scene.scene), 8000.0);
  EXPECT_DOUBLE_EQ(stiffnessScale(800.0, 8000.0), 0.1);
  EXPECT_DOUBLE_EQ(stiffnessScale(800.0, 500.0), 1.0) << "a softer coupling is felt whole";
  EXPECT_DOUBLE_EQ(stiffnessScale(std::numeric_limits<double>::infinity(), 8000.0), 1.0) << "a simulated device";
  for (const double share : {1.0, 0.25, 0.1}) {
    ClientInteraction c(b.scene);
    const RenderLimits limits{30.0, 1.0, false, 0.025, share};
    c.render(Vector3::Zero(), Vector3::Zero(), false, false, 0.001, limits);  // arms the start-up guard
    Vector3 rendered = Vector3::Zero();
    for (int k = 0; k < 100; ++k) rendered = c.render(Vector3(0, 0, 8.0), Vector3::Zero(), false, false, 0.001, limits);
    EXPECT_NEAR(rendered.z(), 8.0 * share, 1e-9) << share;
  }
}

}  // namespace
}  // namespace igms
