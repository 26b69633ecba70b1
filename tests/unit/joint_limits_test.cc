// Joint limits (core/simulation/joint_limits.h) on the 7-dof arm and, when
// example-robot-data is fetched, the Panda: a joint thrown at its limit stops
// there and gives back no energy, under every integrator; a pull cannot drag
// joints past their limits (it does with the limits off); a run that stays
// inside its limits is bit for bit the run without them.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/dynamics/crba.h"
#include "core/simulation/simulation.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

double kineticEnergy(const Simulation& sim) {
  Data d(sim.model());
  const MatrixX H = crba(sim.model(), d, sim.q()).dense();
  return 0.5 * sim.v().dot(H * sim.v());
}

// The largest distance of any limited joint beyond its limit.
double beyondLimits(const Simulation& sim) {
  const Model& m = sim.model();
  double worst = 0.0;
  for (int j = 0; j < m.nb; ++j) {
    if (m.joint_nv[static_cast<size_t>(j)] != 1) continue;
    const int v = m.v_index[static_cast<size_t>(j)];
    const double x = sim.q()[m.q_index[static_cast<size_t>(j)]];
    worst = std::max({worst, x - m.upper[static_cast<size_t>(v)], m.lower[static_cast<size_t>(v)] - x});
  }
  return worst;
}

Scene arm(const std::string& extra, const std::string& simulation) {
  return parseScene("robot: {model: ../models/arm7.urdf}\n" + extra + "simulation: {" + simulation + "}\n",
                    "arm7_limits.yaml", sourceDir() + "/scenes");
}

// The last joint (limits +-2.8973 rad), free, no gravity, no damping, thrown at 2 rad/s: it reaches its
// upper limit after 1.45 s, stops within a few mrad of it and rebounds with a few percent of its energy.
// The energy never rises above what it was thrown with.
TEST(JointLimits, AJointThrownAtItsLimitStopsThereAndGivesBackNoEnergy) {
  for (const char* integrator : {"linearly_implicit", "semi_implicit_euler", "rk4"}) {
    Simulation sim(arm("gravity: [0, 0, 0]\ninitial: {q: [0, 0, 0, -1.5, 0, 1.5, 0], v: [0, 0, 0, 0, 0, 0, 2.0]}\n",
                       std::string("integrator: ") + integrator + ", joint_damping: false"));
    const double e0 = kineticEnergy(sim);
    double highest = e0, deepest = 0.0;
    for (int k = 0; k < 2500; ++k) {
      ASSERT_TRUE(sim.step(nullptr)) << integrator;
      highest = std::max(highest, kineticEnergy(sim));
      deepest = std::max(deepest, beyondLimits(sim));
    }
    std::printf("%-20s thrown at the limit: %.2f mrad beyond at most, kinetic energy %.4f J -> %.2e J, highest %.6f J\n",
                integrator, 1000 * deepest, e0, kineticEnergy(sim), highest);
    EXPECT_LE(highest, e0 * (1 + 1e-6)) << integrator << ": the limit gives back no energy";
    EXPECT_LT(kineticEnergy(sim), 0.05 * e0) << integrator << ": a damped stop, at most a small rebound";
    EXPECT_GT(deepest, 0.0) << integrator << ": it reached the limit";
    EXPECT_LT(deepest, 0.01) << integrator << ": and stopped within 10 mrad of it";
  }
}

// A pull on the flange at the force cap of the paper's scenes (60 N) for 2 s, on the arm under gravity
// (the hold of an interaction): with the limits off it drags joints far past them. (At 200 N the last
// joint sinks 58 mrad: the spring's give, proportional to the force.)
TEST(JointLimits, APullCannotDragAJointPastItsLimit) {
  double beyond[2] = {0.0, 0.0};
  for (int on = 0; on < 2; ++on) {
    Simulation sim(arm("initial: {q: [2.5, 0.5, 0, -1.0, 0, 1.5, 2.5]}\n"
                       "interaction: {pull: {k: 800, b: 20, max_force: 60, max_stretch: 0.3, link: flange}}\n",
                       std::string("joint_limits: ") + (on ? "true" : "false")));
    InteractionInput pull;
    pull.mode = InteractionMode::Pull;
    pull.attach_frame = sim.model().frameIndex("flange");
    for (int k = 0; k < 2000; ++k) {
      // The hand keeps 1 m to the robot's left of the flange: always the cap, always dragging.
      pull.tip_position = sim.linkPoses()[static_cast<size_t>(pull.attach_frame)].p + Vector3(0.0, 1.0, 0.0);
      pull.seq = k;
      ASSERT_TRUE(sim.step(&pull));
      beyond[on] = std::max(beyond[on], beyondLimits(sim));
    }
  }
  std::printf("pulled 2 s at the cap: beyond the limits by %.3f rad with them off, %.4f rad with them on\n", beyond[0],
              beyond[1]);
  EXPECT_GT(beyond[0], 0.2) << "the pull does drag the joints past their limits when nothing stops them";
  EXPECT_LT(beyond[1], 0.03) << "with the limits on, the spring's sinking under 60 N at most";
}

TEST(JointLimits, InsideTheLimitsTheDynamicsAreUnchangedBitForBit) {
  Scene with = loadScene(sourceDir() + "/scenes/quadruped_float.yaml"), without = with;
  with.joint_limits = true;
  without.joint_limits = false;
  Simulation a(with), b(without);
  for (int k = 0; k < 1000; ++k) {
    ASSERT_TRUE(a.step(nullptr));
    ASSERT_TRUE(b.step(nullptr));
    ASSERT_LE(beyondLimits(a), 0.0) << "the run stays inside its limits";
    ASSERT_EQ(a.q(), b.q()) << "step " << k;
    ASSERT_EQ(a.v(), b.v()) << "step " << k;
  }
}

// The finding this came from: on a Panda pull the 15 g fingers slid to -0.25 and +0.29 m against
// URDF limits of 0 to 0.04 m.
TEST(JointLimits, ThePandasFingersStayInTheirRangeThroughAPull) {
  const std::string scene_file = sourceDir() + "/scenes/panda_obstacle.yaml";
  if (!std::filesystem::exists(sourceDir() + "/third_party/example-robot-data/robots/panda_description"))
    GTEST_SKIP() << "example-robot-data not fetched (scripts/setup/fetch_robots.sh)";
  Simulation sim(loadScene(scene_file));
  const Model& m = sim.model();
  InteractionInput pull;
  pull.mode = InteractionMode::Pull;
  const int hand = std::max(0, sim.pullFrame());
  const Vector3 start = sim.linkPoses()[static_cast<size_t>(hand)].p;
  double finger_lo = 1e9, finger_hi = -1e9;
  for (int k = 0; k < 3000; ++k) {
    // Up and to the left by 15 cm over 0.7 s, then held, as scenes/panda_pull.yaml does.
    const double s = std::min(1.0, k / 700.0);
    pull.tip_position = start + s * Vector3(0.0, 0.15, 0.15);
    pull.seq = k;
    ASSERT_TRUE(sim.step(&pull));
    for (const char* finger : {"panda_finger_joint1", "panda_finger_joint2"}) {
      const int j = m.jointIndex(finger);
      ASSERT_GE(j, 0);
      const double x = sim.q()[m.q_index[static_cast<size_t>(j)]];
      finger_lo = std::min(finger_lo, x);
      finger_hi = std::max(finger_hi, x);
    }
  }
  std::printf("Panda pull: fingers between %.4f and %.4f m (limits 0 to 0.04 m)\n", finger_lo, finger_hi);
  EXPECT_GE(finger_lo, -0.001);
  EXPECT_LE(finger_hi, 0.041);
}

}  // namespace
}  // namespace igms::test
