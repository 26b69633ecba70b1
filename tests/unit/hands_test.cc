// Several hands at once: each client's input is its own coupling, the
// couplings add up in the dynamics and in the implicit step, each hand's
// resume ramp is its own, and the order of the inputs does not matter.
#include <gtest/gtest.h>

#include <cstring>

#include "core/dynamics/crba.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/joint_damping.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/simulation/simulation.h"
#include "tests/support/malloc_counter.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

// The hands' bookkeeping on eq. (3) and (4) alone: without the push coupling's damper, whose force
// the robot's own motion sets (a push that returns onto a link moving away can be slack).
Scene scene() {
  Scene s = loadScene(sourceDir() + "/scenes/puma_obstacle.yaml");
  s.push.b = 0.0;
  return s;
}

Vector3 framePosition(Simulation& sim, const std::string& frame) {
  return sim.linkPoses()[static_cast<size_t>(sim.model().frameIndex(frame))].p;
}

// One person pushes link 2 (the tip 1 cm into its surface), another pulls the end-effector.
struct TwoHands {
  InteractionInput push, pull;
  explicit TwoHands(Simulation& sim) {
    const Model& m = sim.model();
    const SE3 link2 = sim.linkPoses()[static_cast<size_t>(m.frameIndex("link2"))];
    push.mode = InteractionMode::Push;
    // Link 2's cylinder: axis along x through (0.2159, 0, 0.08), radius 7 cm; the tip sphere's centre
    // 6 mm outside its surface, 4 mm deep with its radius (a push starts at most 5 mm deep: proxy.h).
    push.tip_position = link2.act(Vector3(0.2159, 0.0, 0.156));
    push.tip_radius = 0.01;
    push.client = 2;
    push.seq = 1;
    pull.mode = InteractionMode::Pull;
    pull.tip_position = framePosition(sim, "ee_link") + Vector3(0.05, 0.05, 0.0);
    pull.client = 1;
    pull.seq = 1;
  }
};

// Under the explicit step, whose forces are their start values (the linearly-implicit step reports the
// forces it applied at its end: applied_force_test).
TEST(Hands, TwoHandsMoveTheRobotAsTheSumOfBothCouplings) {
  Scene explicit_step = scene();
  explicit_step.integrator = IntegratorKind::SemiImplicitEuler;
  Simulation sim(explicit_step);
  TwoHands h(sim);
  HandInputs both;
  both.add(h.push);
  both.add(h.pull);
  const VectorX q = sim.q(), v = sim.v();
  ASSERT_TRUE(sim.step(both));
  const StepOutcome& o = sim.outcome();
  ASSERT_EQ(o.nhands, 2);
  EXPECT_EQ(o.hands[0].client, 1) << "client-id order";
  EXPECT_EQ(o.hands[1].client, 2);
  EXPECT_EQ(o.hands[0].mode, InteractionMode::Pull);
  EXPECT_EQ(o.hands[1].mode, InteractionMode::Push);
  ASSERT_GT(o.hands[0].applied.force.norm(), 1.0);
  ASSERT_GT(o.hands[1].applied.force.norm(), 1.0) << "the push must touch link 2";
  EXPECT_LE((o.force_on_robot - o.hands[0].applied.force - o.hands[1].applied.force).norm(), 1e-12);
  // The step's acceleration is forward dynamics under J1^T F1 + J2^T F2 at the start state.
  const Model& m = sim.model();
  Data d(m);
  bodyKinematics(m, d, q);
  VectorX tau = sim.tau();
  for (int k = 0; k < 2; ++k) {
    const HandOutcome& ho = o.hands[static_cast<size_t>(k)];
    const int f = ho.mode == InteractionMode::Pull ? m.frameIndex("ee_link") : m.frameIndex("link2");
    Matrix6X J(6, m.nv);
    const SE3 X = framePose(m, d, f);
    pointJacobian(m, d, f, X.inverse().act(ho.applied.point), J);
    tau += J.topRows<3>().transpose() * ho.applied.force;
  }
  crba(m, d, q);
  tau -= sim.scene().robots[0].hold_damping * d.H.symmetricUpperTimes(v);
  if (sim.scene().joint_damping) tau -= jointDamping(m).cwiseProduct(v);
  ASSERT_TRUE(forwardDynamics(m, d, q, v, tau));
  EXPECT_LE((d.qdd - sim.qdd()).norm(), 1e-9 * std::max(1.0, d.qdd.norm()));
}

TEST(Hands, TheInputsOrderDoesNotChangeTheStepBitForBit) {
  Simulation a(scene()), b(scene());
  TwoHands h(a);
  HandInputs ab, ba;
  ab.add(h.pull);
  ab.add(h.push);
  ba.add(h.push);
  ba.add(h.pull);
  for (int k = 0; k < 300; ++k) {
    ASSERT_TRUE(a.step(ab));
    ASSERT_TRUE(b.step(ba));
  }
  EXPECT_EQ(std::memcmp(a.q().data(), b.q().data(), sizeof(double) * static_cast<size_t>(a.q().size())), 0);
  EXPECT_EQ(std::memcmp(a.v().data(), b.v().data(), sizeof(double) * static_cast<size_t>(a.v().size())), 0);
}

TEST(Hands, AHandThatComesBackAfterAGapRampsInWithoutTouchingTheOther) {
  Simulation sim(scene());
  TwoHands h(sim);
  HandInputs both, pull_only;
  both.add(h.push);
  both.add(h.pull);
  pull_only.add(h.pull);
  for (int k = 0; k < 10; ++k) {
    ++h.pull.seq;
    ++h.push.seq;
    both.in[0] = h.push;
    both.in[1] = h.pull;
    ASSERT_TRUE(sim.step(both));
  }
  const double full = sim.outcome().hands[1].applied.force.norm();  // the push's (client 2)
  for (int k = 0; k < 50; ++k) {  // the pusher is away 50 steps: a gap for it only
    ++h.pull.seq;
    pull_only.in[0] = h.pull;
    ASSERT_TRUE(sim.step(pull_only));
  }
  const int64_t ramps = sim.resumeRamps();
  ++h.pull.seq;
  ++h.push.seq;
  both.in[0] = h.push;
  both.in[1] = h.pull;
  ASSERT_TRUE(sim.step(both));
  EXPECT_EQ(sim.resumeRamps(), ramps + 1) << "the returning hand ramps in";
  const HandOutcome& pull = sim.outcome().hands[0];
  const HandOutcome& push = sim.outcome().hands[1];
  ASSERT_GT(full, 1.0);
  EXPECT_GT(push.applied.force.norm(), 0.0);
  EXPECT_LT(push.applied.force.norm(), 0.05 * full) << "the returning push starts at 1/100 of its force";
  EXPECT_GT(pull.applied.force.norm(), 0.5) << "the pull, never away, keeps acting in full";
}

// A hand holds the robot it pushes or pulls, and holds it while its push goes on, even where the tip
// slides off for a while; the robot goes back to its trajectory (a replan) the step the push ends. A
// push that touches no robot holds none: the robot follows its trajectory bit for bit.
TEST(Hands, AHandHoldsTheRobotItActsOnUntilItLetsGo) {
  Simulation touched(scene()), untouched(scene()), alone(scene());
  TwoHands h(touched);
  InteractionInput nowhere = h.push;
  nowhere.tip_position = Vector3(3.0, 3.0, 3.0);
  for (int k = 0; k < 200; ++k) {
    ASSERT_TRUE(untouched.step(&nowhere));
    ASSERT_TRUE(alone.step(nullptr));
    EXPECT_FALSE(untouched.outcome().replanned);
  }
  EXPECT_EQ(0, std::memcmp(untouched.q().data(), alone.q().data(), sizeof(double) * untouched.q().size()))
      << "a push on nothing held the robot";
  InteractionInput push = h.push;
  int replans = 0, pushed = 0;
  for (int k = 0; k < 50; ++k, ++push.seq) {  // on link 2
    ASSERT_TRUE(touched.step(&push));
    pushed += touched.outcome().force_on_robot.norm() > 0.0;
    replans += touched.outcome().replanned;
  }
  ASSERT_GT(pushed, 10) << "the push must touch link 2";
  push.tip_position = Vector3(3.0, 3.0, 3.0);  // slides off: the push goes on, touching nothing
  for (int k = 0; k < 50; ++k, ++push.seq) {
    ASSERT_TRUE(touched.step(&push));
    EXPECT_EQ(touched.outcome().force_on_robot.norm(), 0.0);
    replans += touched.outcome().replanned;
  }
  EXPECT_EQ(replans, 0) << "the robot was let go while the hand still pushed";
  push.mode = InteractionMode::None;
  ASSERT_TRUE(touched.step(&push));
  EXPECT_TRUE(touched.outcome().replanned) << "the push ended: generation resumes from the new state";
}

TEST(Hands, AStepWithFourHandsDoesNotAllocate) {
  Simulation sim(scene());
  TwoHands h(sim);
  HandInputs four;
  for (int c = 0; c < 4; ++c) {
    InteractionInput in = c % 2 ? h.push : h.pull;
    in.client = 10 + c;
    four.add(in);
  }
  EXPECT_FALSE(four.add(h.pull)) << "at most kMaxHands";
  ASSERT_TRUE(sim.step(four));
  const size_t n = allocationsDuring([&] {
    for (int k = 0; k < 50; ++k) sim.step(four);
  });
  EXPECT_EQ(n, 0u);
}

}  // namespace
}  // namespace igms::test
