// Issue 43, item 2: the push's virtual coupling, a spring and a damper between the device and its
// proxy: c = k_p d + b d', never below zero. The scene states it (interaction.coupling) and its load
// refuses a damper below k T / 2 (Colgate and Schenkel); the server applies it and the client renders
// it against the estimate. Without the damper a rigid hand pushing a box makes it ring; with the
// default it is steady.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "haptic_client/servo/client_interaction.h"
#include "core/model/environment_model.h"
#include "core/simulation/simulation.h"
#include "tests/support/malloc_counter.h"
#include "tests/support/test_models.h"
#include "tools/scenario/scenario_run.h"

namespace igms {
namespace {

const char* kBox =
    "ground: {height: 0, material: wood}\n"
    "materials: {wood: {friction: 0.5}}\n"
    "bodies:\n  - {name: box, shape: box, size: [0.2, 0.2, 0.2], mass: 1.0, xyz: [0, 0, 0.1], material: wood}\n"
    "simulation: {integrator: linearly_implicit, dt: 0.001, rate_hz: 1000}\n";

Scene boxScene(const std::string& interaction) {
  return parseScene(std::string(kBox) + "interaction:\n" + interaction, "coupling.yaml",
                    test::sourceDir() + "/scenes");
}

std::string loadError(const std::string& interaction) {
  try {
    boxScene(interaction);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(VirtualCoupling, TheSceneStatesItAndItsLoadChecksItIsPassive) {
  const Scene plain = boxScene("  push: {k_p: 3000}\n");
  EXPECT_DOUBLE_EQ(plain.push.b, kCouplingTime * 3000) << "the default damper";
  const Scene given = boxScene("  push: {max_force: 40}\n  coupling: {k: 2500, b: 12}\n");
  EXPECT_DOUBLE_EQ(given.push.k_p, 2500) << "coupling.k is the push's spring";
  EXPECT_DOUBLE_EQ(given.push.b, 12);
  EXPECT_DOUBLE_EQ(boxScene("  push: {k_p: 3000}\n  coupling: {b: 1.5}\n").push.b, 1.5) << "k T / 2 exactly passes";
  const std::pair<const char*, const char*> bad[] = {
      {"  push: {k_p: 3000}\n  coupling: {b: 1.4}\n",
       "coupling.yaml:8: interaction.coupling.b: 1.4 N s/m is below k T / 2 = 1.5 N s/m at the scene's 1000 Hz"},
      {"  push: {k_p: 3000}\n  coupling: {b: -1}\n", "interaction.coupling.b: must be >= 0"},
      {"  push: {k_p: 3000}\n  coupling: {k: 2000}\n", "interaction.coupling.k: is interaction.push.k_p"},
      {"  coupling: {b: 30}\n", "interaction.coupling: couples the push: needs interaction.push"},
      {"  push: {k_p: 3000}\n  coupling: {damping: 30}\n", "interaction.coupling.damping: unknown key"},
  };
  for (const auto& [yaml, expected] : bad) EXPECT_NE(loadError(yaml).find(expected), std::string::npos) << loadError(yaml);
}

// The server's push on a box that friction holds still (the pushes below stay under mu m g = 4.9 N):
// the step applies the spring at its end plus the damper on the tip's approach, k_p d + b v_tip; a tip
// leaving faster than the spring relaxes pushes with nothing (never pulls).
TEST(VirtualCoupling, TheServerAppliesTheSpringAndTheDamperAndNeverPulls) {
  const Scene scene = boxScene("  push: {k_p: 3000, max_force: 40, tip_radius: 0.01}\n  coupling: {b: 30}\n");
  for (const double v_tip : {0.0, 0.02, 0.05, -0.05, -0.2}) {
    Simulation sim(scene);
    for (int k = 0; k < 20; ++k) ASSERT_TRUE(sim.step(nullptr));  // settled on the floor
    InteractionInput in;
    in.mode = InteractionMode::Push;
    in.client = 1;
    in.seq = 1;
    in.tip_radius = 0.01;
    const double depth = 0.001;
    in.tip_position = Vector3(-0.1 - in.tip_radius + depth, 0, 0.1);
    in.tip_velocity = Vector3(v_tip, 0, 0);
    ASSERT_TRUE(sim.step(&in));
    const double expected = std::max(0.0, 3000 * depth + 30 * v_tip);
    EXPECT_NEAR(sim.outcome().force_on_robot.x(), expected, 1e-9) << "tip at " << v_tip << " m/s";
    EXPECT_NEAR(sim.v().head(3).norm(), 0.0, 1e-12) << "static friction holds the box";
  }
}

// The client renders the same law against its estimate: the touched point's velocity from the
// estimate's link velocities, or without them from its last two poses (here the box moving at 3 cm/s
// toward the tip).
TEST(VirtualCoupling, TheClientRendersTheDamperAgainstTheEstimatesMotion) {
  const Scene scene = boxScene("  push: {k_p: 3000, max_force: 40, tip_radius: 0.01}\n  coupling: {b: 30}\n");
  const ResolvedScene resolved = resolveScene(scene);
  for (const bool given : {true, false}) {
    ClientInteraction client(resolved);
    Simulation sim(resolved);
    std::vector<SE3> links = sim.linkPoses();
    const size_t box = links.size() - 1;
    const double v_box = -0.03, v_tip = 0.01, h = 0.001;
    std::vector<Motion> velocities(links.size());
    velocities[box].v = Vector3(v_box, 0, 0);
    const Vector3 start = links[box].p;
    Vector3 tip(-0.1 - 0.01 - 0.002, 0, 0.1);  // 2 mm in front of the box
    Vector3 felt = Vector3::Zero();
    for (int k = 0; k < 200; ++k) {
      links[box].p = start + Vector3(v_box * h * k, 0, 0);
      tip.x() += v_tip * h;
      haptic_input_t msg{};
      client.fillInput(tip, Vector3(v_tip, 0, 0), 0, msg);
      felt = client.userForce(links, h * k, tip, Vector3(v_tip, 0, 0), given ? &velocities : nullptr);
    }
    const double depth = (tip.x() + 0.01) - (links[box].p.x() - 0.1);
    ASSERT_GT(depth, 0.0);
    EXPECT_NEAR(felt.x(), -(3000 * depth + 30 * (v_tip - v_box)), 1e-9) << "4 cm/s closing; velocities given: " << given;
    EXPECT_NEAR(felt.y(), 0.0, 1e-12);
  }
}

// The servo loop's side of it allocates nothing: the damper against given velocities or differences.
TEST(VirtualCoupling, TheClientsCouplingAllocatesNothing) {
  const ResolvedScene resolved = resolveScene(
      boxScene("  push: {k_p: 3000, max_force: 40, tip_radius: 0.01}\n  coupling: {b: 30}\n"));
  Simulation sim(resolved);
  std::vector<SE3> links = sim.linkPoses();
  const std::vector<Motion> velocities(links.size());
  for (const bool given : {true, false}) {
    ClientInteraction client(resolved);
    haptic_input_t msg{};
    msg.contact_link.reserve(64);
    msg.attach_link.reserve(64);
    int k = 0;
    auto cycle = [&] {
      const Vector3 tip(-0.1 - 0.01 + 0.001 * std::min(1.0, 0.01 * k), 0, 0.1);
      client.fillInput(tip, Vector3(0.01, 0, 0), 0, msg);
      client.render(client.userForce(links, 0.001 * k, tip, Vector3(0.01, 0, 0), given ? &velocities : nullptr),
                    Vector3(0.01, 0, 0), false, false, 0.001, RenderLimits{});
      ++k;
    };
    for (int i = 0; i < 5; ++i) cycle();  // warm
    EXPECT_EQ(test::allocationsDuring([&] {
                for (int i = 0; i < 200; ++i) cycle();
              }),
              0u)
        << "velocities given: " << given;
  }
}

double rippleAfter(const ScenarioResult& r, double from, double to, double* mean) {
  double s = 0, s2 = 0;
  int n = 0;
  for (const ScenarioSample& x : r.samples)
    if (x.t >= from && x.t <= to) {
      s += x.rendered.x();
      s2 += x.rendered.x() * x.rendered.x();
      ++n;
    }
  *mean = s / n;
  return std::sqrt(std::max(0.0, s2 / n - *mean * *mean));
}

// A rigid hand (the script's targets followed exactly) pushes the box at 5 cm/s: with eq. (3)'s spring
// alone the box rings against it; the coupling's default damper settles it to mu m g.
TEST(VirtualCoupling, TheDefaultDamperMakesTheRigidHandsBoxPushSteady) {
  Scene scene = loadScene(test::sourceDir() + "/scenes/truth/box_push.yaml");
  const std::string script = test::sourceDir() + "/scenes/truth/box_push_rigid.yaml";
  const double mu_m_g = 0.5 * 1.0 * 9.81;
  double mean = 0;
  // Contact at 0.6 s; steady from 1.1 s.
  const double steady = rippleAfter(runScenario(scene, script, 3.6), 1.1, 3.5, &mean);
  EXPECT_NEAR(-mean, mu_m_g, 0.01 * mu_m_g);
  EXPECT_LT(steady, 0.01 * mu_m_g) << "default b = " << scene.push.b << " N s/m";
  // The law before the coupling (the load would refuse it): the box rings against the spring at
  // sqrt(k_p / m) = 8.7 Hz, over 5 % of mu m g for the first steady second, dying out only by the
  // implicit step's own numerical damping (measured: 0.29 N over 1.1-2 s, 0.05 N over 2.8-3.5 s).
  scene.push.b = 0.0;
  const double undamped = rippleAfter(runScenario(scene, script, 3.6), 1.1, 2.0, &mean);
  EXPECT_GT(undamped, 0.05 * mu_m_g) << "eq. (3) alone against a rigid hand rings";
  EXPECT_GT(undamped, 20 * steady);
}

}  // namespace
}  // namespace igms
