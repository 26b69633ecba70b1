// The server loop's step (server/loop/stepper): which input a step consumes
// under each clock, and the snapshot it leaves for the publisher.
#include <gtest/gtest.h>

#include "core/realtime/clock.h"
#include "server/loop/stepper.h"
#include "server/transport/input_gate.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

struct Rig {
  explicit Rig(bool lockstep)
      : sim(loadScene(sourceDir() + "/scenes/puma_wall.yaml")), ring(sim.model(), 4),
        stepper(sim, hands, ring, status, lockstep, /*input_hold_s=*/0.05) {}
  void send(int64_t seq, double age_s, int slot = 0, int32_t client = 7) {
    TimedInput in;
    in.input.seq = seq;
    in.input.client = client;
    in.arrived = monotonicSeconds() - age_s;
    hands[static_cast<size_t>(slot)].write(in);
  }
  int64_t consumedSeq() {
    const Snapshot* s = ring.beginRead();
    EXPECT_NE(s, nullptr);
    const int64_t seq = s ? s->outcome.input_seq : -2;
    ring.endRead();
    return seq;
  }
  Simulation sim;
  HandSlots hands;
  SnapshotRing ring;
  LoopStatus status;
  Stepper stepper;
};

TEST(Stepper, RealtimeHoldsAnInputForItsHoldTimeThenStepsWithout) {
  Rig rig(/*lockstep=*/false);
  EXPECT_FALSE(rig.stepper.inputPending());
  ASSERT_TRUE(rig.stepper.step());
  EXPECT_EQ(rig.consumedSeq(), -1) << "no input yet";
  rig.send(5, 0.0);
  EXPECT_TRUE(rig.stepper.inputPending());
  ASSERT_TRUE(rig.stepper.step());
  EXPECT_EQ(rig.consumedSeq(), 5);
  ASSERT_TRUE(rig.stepper.step());
  EXPECT_EQ(rig.consumedSeq(), 5) << "held: the client may miss a cycle";
  rig.send(6, 0.2);  // older than the 50 ms hold
  ASSERT_TRUE(rig.stepper.step());
  EXPECT_EQ(rig.consumedSeq(), -1) << "a stale input acts no more";
  EXPECT_EQ(rig.status.steps.load(), 4);
  EXPECT_EQ(rig.status.consumed_inputs.load(), 2);
}

TEST(Stepper, LockstepUsesEachInputWhateverItsAgeAndCountsRingDrops) {
  Rig rig(/*lockstep=*/true);
  rig.send(1, 10.0);
  ASSERT_TRUE(rig.stepper.step());
  EXPECT_FALSE(rig.stepper.inputPending());
  EXPECT_EQ(rig.consumedSeq(), 1);
  for (int k = 0; k < 6; ++k) ASSERT_TRUE(rig.stepper.step());  // nobody drains: a ring of 4
  EXPECT_EQ(rig.status.ring_drops.load(), 2);
  EXPECT_NEAR(rig.sim.time(), 0.007, 1e-12);
}

// Loss is visible: inputs that never arrived show as gaps in each client's seq
// (counted per client, never across clients); stale ones are rejected.
TEST(InputGate, GapsInEachClientsSeqAreCountedAsMissed) {
  Simulation sim(loadScene(sourceDir() + "/scenes/puma_wall.yaml"));
  InputGate gate(sim.model(), 5);
  auto input = [](int32_t client, int64_t seq) {
    haptic_input_t m{};
    m.session_token = 5;
    m.client_id = client;
    m.seq = seq;
    m.tip_radius = 0.01;
    return m;
  };
  InteractionInput out;
  RejectReason why;
  for (int64_t seq : {1, 2, 3, 7, 8, 20}) EXPECT_TRUE(gate.admit(input(1, seq), &out, &why)) << seq;
  for (int64_t seq : {100, 101, 105}) EXPECT_TRUE(gate.admit(input(2, seq), &out, &why)) << seq;
  EXPECT_FALSE(gate.admit(input(1, 19), &out, &why));
  EXPECT_EQ(why, RejectReason::Stale);
  EXPECT_EQ(gate.missed(), 3 + 11 + 3) << "4-6 and 9-19 of client 1, 102-104 of client 2";
}

}  // namespace
}  // namespace igms::test
