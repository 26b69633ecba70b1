// The server loop's step (server/loop/stepper): which input a step consumes
// under each clock, and the snapshot it leaves for the publisher.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "core/realtime/clock.h"
#include <lcm/lcm-cpp.hpp>

#include "server/loop/stepper.h"
#include "server/transport/bus_receiver.h"
#include "server/transport/input_gate.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

struct SceneText {
  std::string yaml;
};

struct Rig {
  explicit Rig(bool lockstep, const std::string& scene = "puma_wall.yaml", int contact_every = 0)
      : sim(loadScene(sourceDir() + "/scenes/" + scene)),
        ring(sim.model(), 4, sim.contactModel() ? sim.contactModel()->capacity() : 0),
        stepper(sim, hands, ring, status, lockstep, /*input_hold_s=*/0.05, contact_every) {}
  Rig(bool lockstep, const SceneText& scene)
      : sim(parseScene(scene.yaml, "test.yaml", sourceDir() + "/scenes")),
        ring(sim.model(), 4, sim.contactModel() ? sim.contactModel()->capacity() : 0),
        stepper(sim, hands, ring, status, lockstep, /*input_hold_s=*/0.05, 0) {}
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

// The loop standing still (SIGSTOP, a starved machine) does not age the inputs: a hand that leaned on a
// box through an 80 ms stall of igms-server went on acting only for the first step after it (the hold is
// 50 ms), then came back as a resume ramp from zero, and the box fell onto the tip (4.3 N felt against
// 1.6 N held in scripts/bench/haptic_truth.py's tall_box_tip). Time before the stall still counts.
TEST(Stepper, TheLoopsOwnStallDoesNotAgeTheInputs) {
  Rig rig(/*lockstep=*/false);
  ASSERT_TRUE(rig.stepper.step());
  EXPECT_EQ(rig.consumedSeq(), -1);
  rig.send(5, 0.0);
  ASSERT_TRUE(rig.stepper.step());
  EXPECT_EQ(rig.consumedSeq(), 5);
  std::this_thread::sleep_for(std::chrono::milliseconds(80));  // the loop stands 80 ms
  ASSERT_TRUE(rig.stepper.step());
  EXPECT_EQ(rig.consumedSeq(), 5) << "it arrived just before the stall: it still acts";
  rig.send(6, 0.03);  // arrived 30 ms ago, then the loop stands 30 ms: 60 ms old, less the stall's 30
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  ASSERT_TRUE(rig.stepper.step());
  EXPECT_EQ(rig.consumedSeq(), 6) << "its 30 ms before the stall are within the hold";
  rig.send(7, 0.2);  // 200 ms old when it arrived... before a stall of 30 ms
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  ASSERT_TRUE(rig.stepper.step());
  EXPECT_EQ(rig.consumedSeq(), -1) << "stale before the stall: a stall does not bring it back";
}

// A realtime step that runs late (the loop catching up after a stall, back to back) takes each hand's
// inputs in the order the hand made them, skipping one lost on the way; an on-time step takes the
// newest. The newest would pair every catch-up step with where the hand is now: a hand at 1 mm/s
// through a 30 ms stall moved a leaning box 13 um from where the client's model had it, and the hand
// felt +0.065 N (scripts/bench/haptic_truth.py's tall_box_tip).
TEST(Stepper, ALateStepTakesTheInputsInOrder) {
  Rig rig(/*lockstep=*/false);
  rig.send(5, 0.0);
  ASSERT_TRUE(rig.stepper.step());
  EXPECT_EQ(rig.consumedSeq(), 5);
  for (int64_t seq : {6, 8, 9, 10}) rig.send(seq, 0.0);  // 7 lost on the way
  ASSERT_TRUE(rig.stepper.step(/*late=*/true));
  EXPECT_EQ(rig.consumedSeq(), 6) << "the next in order";
  ASSERT_TRUE(rig.stepper.step(/*late=*/true));
  EXPECT_EQ(rig.consumedSeq(), 8) << "7 never came: the one after it";
  ASSERT_TRUE(rig.stepper.step(/*late=*/false));
  EXPECT_EQ(rig.consumedSeq(), 10) << "on time again: the newest";
  ASSERT_TRUE(rig.stepper.step(/*late=*/true));
  EXPECT_EQ(rig.consumedSeq(), 10) << "late, but nothing newer: held";
  EXPECT_EQ(rig.status.consumed_inputs.load(), 4) << "5, 6, 8, 10";
  rig.send(11, 0.0, 0, /*client=*/8);  // another client in the slot: its seq says nothing of the last one's
  rig.send(12, 0.0, 0, /*client=*/8);
  ASSERT_TRUE(rig.stepper.step(/*late=*/true));
  EXPECT_EQ(rig.consumedSeq(), 12);
}

// The contacts ride on every contact_every-th step's snapshot: the 1 kg box at
// rest on the 20 degree slope is held by forces that sum to its weight.
TEST(Stepper, SnapshotsCarryTheContactsOnTheStepsTheyAreDue) {
  Rig rig(/*lockstep=*/true, "box_slope.yaml", /*contact_every=*/3);
  const int box = rig.sim.model().frameIndex("box");
  ASSERT_GE(box, 0);
  int due = 0;
  for (int k = 1; k <= 9; ++k) {
    ASSERT_TRUE(rig.stepper.step());
    const Snapshot* s = rig.ring.beginRead();
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->contacts_due, s->seq % 3 == 0) << "step " << s->seq;
    if (s->contacts_due) {
      ++due;
      EXPECT_EQ(s->contacts_total, rig.sim.contacts().n);
      ASSERT_GE(s->ncontacts, 1);
      Vector3 on_box = Vector3::Zero();
      for (int c = 0; c < s->ncontacts; ++c) {
        const PublishedContact& p = s->contacts[static_cast<size_t>(c)];
        ASSERT_TRUE(p.link_a == box || p.link_b == box);
        EXPECT_TRUE(p.link_a == -1 || p.link_b == -1) << "the other side is the ground";
        EXPECT_NEAR(p.normal.norm(), 1.0, 1e-12);
        on_box += p.link_b == box ? p.force : Vector3(-p.force);
      }
      EXPECT_NEAR(on_box.x(), 0.0, 1e-6);
      EXPECT_NEAR(on_box.y(), 0.0, 1e-6);
      EXPECT_NEAR(on_box.z(), 9.81, 1e-3) << "the slope carries the box's weight";
    }
    rig.ring.endRead();
  }
  EXPECT_EQ(due, 3);
}

// What the step cut short or left out rides on every snapshot, for the status (server_status_t): 60
// balls heaped on one spot overflow contact detection's buffers, and the pairs it dropped are counted.
TEST(Stepper, SnapshotsCarryWhatTheStepLeftOut) {
  std::string yaml = "bodies:\n";
  for (int k = 0; k < 60; ++k)
    yaml += "  - {name: b" + std::to_string(k) + ", shape: sphere, radius: 0.05, mass: 1, xyz: [" +
            std::to_string(1e-4 * k) + ", 0, 1]}\n";
  Rig rig(/*lockstep=*/true, SceneText{yaml});
  ASSERT_TRUE(rig.stepper.step());
  const Snapshot* s = rig.ring.beginRead();
  ASSERT_NE(s, nullptr);
  ASSERT_NE(rig.sim.contactDetection(), nullptr);
  EXPECT_GT(s->candidates_dropped, 0);
  EXPECT_EQ(s->candidates_dropped, rig.sim.contactDetection()->candidatePairsDropped());
  EXPECT_EQ(s->proxy_substep_limited, rig.sim.proxySubstepLimited());
  rig.ring.endRead();
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

// Several hands: realtime, each slot's input holds on its own; lockstep, a step waits for one input
// from each client taking part (up to kLockstepWaitS) and consumes one from each.
TEST(Stepper, EachHandsInputHoldsOnItsOwnAndTheStepTakesThemAll) {
  Rig rig(/*lockstep=*/false);
  rig.send(5, 0.0, /*slot=*/0, /*client=*/1);
  rig.send(9, 0.2, /*slot=*/1, /*client=*/2);  // older than its hold: released
  ASSERT_TRUE(rig.stepper.step());
  const Snapshot* s = rig.ring.beginRead();
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->outcome.nhands, 1);
  EXPECT_EQ(s->outcome.hands[0].client, 1);
  rig.ring.endRead();
  rig.send(10, 0.0, 1, 2);
  ASSERT_TRUE(rig.stepper.step());
  s = rig.ring.beginRead();
  ASSERT_NE(s, nullptr);
  ASSERT_EQ(s->outcome.nhands, 2);
  EXPECT_EQ(s->outcome.hands[0].client, 1);
  EXPECT_EQ(s->outcome.hands[1].client, 2);
  EXPECT_EQ(s->outcome.hands[1].input_seq, 10);
  rig.ring.endRead();
}

TEST(Stepper, LockstepWaitsForEveryClientTakingPart) {
  Rig rig(/*lockstep=*/true);
  rig.send(1, 0.0, 0, 1);
  rig.send(1, 0.0, 1, 2);
  EXPECT_TRUE(rig.stepper.lockstepReady());
  ASSERT_TRUE(rig.stepper.step());
  rig.ring.endRead();
  rig.send(2, 0.0, 0, 1);  // client 2's next has not come yet
  EXPECT_FALSE(rig.stepper.lockstepReady()) << "waits for client 2";
  rig.send(2, 0.0, 1, 2);
  EXPECT_TRUE(rig.stepper.lockstepReady());
  ASSERT_TRUE(rig.stepper.step());
  const Snapshot* s = rig.ring.beginRead();
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->outcome.nhands, 2) << "one input from each";
  rig.ring.endRead();
  // A client that went quiet holds the steps back for kLockstepWaitS at most.
  rig.send(3, 0.0, 0, 1);
  EXPECT_FALSE(rig.stepper.lockstepReady());
  const double until = monotonicSeconds() + Stepper::kLockstepWaitS + 0.005;
  while (monotonicSeconds() < until) {
  }
  EXPECT_TRUE(rig.stepper.lockstepReady());
  ASSERT_TRUE(rig.stepper.step());
  s = rig.ring.beginRead();
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->outcome.nhands, 1) << "only client 1's, client 2 had none waiting";
  rig.ring.endRead();
}

TEST(InputGate, AnOrientationIsCheckedOnlyWhenTheInputHasOne) {
  Simulation sim(loadScene(sourceDir() + "/scenes/puma_wall.yaml"));
  InputGate gate(sim.model(), 5);
  haptic_input_t m{};
  m.session_token = 5;
  m.client_id = 1;
  m.tip_radius = 0.01;
  m.tip_orientation[0] = 2.0;  // not a unit quaternion, but unread: no orientation
  InteractionInput out;
  RejectReason why;
  m.seq = 1;
  EXPECT_TRUE(gate.admit(m, &out, &why));
  EXPECT_FALSE(out.has_orientation);
  m.has_orientation = true;
  m.seq = 2;
  EXPECT_FALSE(gate.admit(m, &out, &why));
  EXPECT_EQ(why, RejectReason::Range);
  m.tip_orientation[0] = 1.0;
  m.attach_orientation[0] = NAN;
  m.seq = 3;
  EXPECT_FALSE(gate.admit(m, &out, &why));
  EXPECT_EQ(why, RejectReason::NonFinite);
  m.attach_orientation[0] = 0.0;
  m.attach_orientation[3] = 1.0;  // 180 degrees about z
  m.tip_angular_velocity[1] = 2.0;
  m.seq = 4;
  ASSERT_TRUE(gate.admit(m, &out, &why));
  EXPECT_TRUE(out.has_orientation);
  EXPECT_NEAR(out.attach_orientation.z(), 1.0, 1e-12);
  EXPECT_NEAR(out.tip_angular_velocity.y(), 2.0, 1e-12);
  ASSERT_EQ(gate.clients().size(), 1u);
  EXPECT_EQ(gate.clients()[0].admitted, 2);
  EXPECT_EQ(gate.clients()[0].rejected, 2);
}

// A fifth client while four hands are active is refused and counted (hands_full), against its own
// record; the four keep their slots. (memq://: LCM in process, no socket.)
TEST(BusReceiver, AFifthHandIsRefusedWhileFourAreActive) {
  Simulation sim(loadScene(sourceDir() + "/scenes/puma_wall.yaml"));
  lcm::LCM bus("memq://");
  ASSERT_TRUE(bus.good());
  bus::MessageVerifier verifier(std::nullopt, "stepper_test");
  BusReceiver receiver(bus, verifier);
  receiver.startSession(sim.model(), 5);
  std::vector<uint8_t> buffer(4096);
  auto send = [&](int32_t client, int64_t seq) {
    haptic_input_t m{};
    m.session_token = 5;
    m.client_id = client;
    m.seq = seq;
    m.tip_radius = 0.01;
    m.tip_orientation[0] = m.attach_orientation[0] = 1.0;
    const int n = m.encode(buffer.data(), 0, static_cast<int>(buffer.size()));
    ASSERT_EQ(bus.publish("IGMS_HAPTIC_INPUT", buffer.data(), static_cast<unsigned>(n)), 0);
    ASSERT_GT(bus.handleTimeout(1000), 0);  // the receiver's subscription: checked, decoded, admitted
  };
  for (int32_t c = 1; c <= 5; ++c) send(c, 1);
  const BusCounters counters = receiver.counters();
  EXPECT_EQ(counters.rejected_by_reason[static_cast<size_t>(RejectReason::HandsFull)], 1);
  std::vector<int32_t> seated;
  TimedInput in;
  for (const auto& slot : receiver.hands())
    if (slot.read(&in) > 0) seated.push_back(in.input.client);
  EXPECT_EQ(seated, (std::vector<int32_t>{1, 2, 3, 4}));
  const std::vector<ClientRecord> clients = receiver.clients();
  ASSERT_EQ(clients.size(), 5u);
  EXPECT_EQ(clients[4].id, 5);
  EXPECT_EQ(clients[4].rejected, 1);
  EXPECT_EQ(clients[4].admitted, 0);
  send(2, 2);  // a seated client goes on in its own slot
  EXPECT_EQ(receiver.counters().inputs_rejected, 1);
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
