// The step of the server's loop: every hand's admitted input, one simulation
// step, timed, and its snapshot into the ring for the publisher.
// Realtime: each client's newest input keeps acting for input_hold after it
// arrived (the client may miss a cycle; the time the loop itself stood, a
// stall, does not count); a step that runs late, catching up, takes the
// inputs in their order instead; and a client that goes quiet releases its
// coupling after its own hold without touching the others. Lockstep: a step
// consumes one input from each client taking part (in client-id order, the
// simulation's), so each input drives exactly one step. Allocation-free.
#pragma once

#include <array>

#include "core/simulation/simulation.h"
#include "server/loop/loop_status.h"
#include "server/loop/snapshot.h"
#include "server/transport/hand_slots.h"

namespace igms {

class Stepper {
 public:
  // Lockstep: a client that sent nothing for this long no longer holds the steps back.
  static constexpr double kLockstepQuietS = 0.25;
  // Lockstep: an input waits at most this long for the other clients' before its step runs.
  static constexpr double kLockstepWaitS = 0.02;

  // contact_every: the contacts go with every this many steps' snapshot (0: never).
  Stepper(Simulation& sim, const HandSlots& hands, SnapshotRing& ring, LoopStatus& status, bool lockstep,
          double input_hold_s, int contact_every)
      : sim_(sim), hands_(hands), ring_(ring), status_(status), lockstep_(lockstep), input_hold_(input_hold_s),
        contact_every_(contact_every) {
    used_client_.fill(-1);
  }

  // An input arrived that no step has consumed yet.
  bool inputPending() const;
  // Lockstep: every client taking part (heard within kLockstepQuietS) has an
  // input waiting, or the first waiting one has waited kLockstepWaitS.
  bool lockstepReady();
  // One step; `late`: it starts after its deadline (realtime: the loop catching up), so each hand's
  // inputs are taken in order rather than the newest. \return false when the simulation diverged (its
  // report says why).
  bool step(bool late = false);
  // The current state into the ring (the initial state; after each step).
  void snapshot(int32_t step_us);

 private:
  Simulation& sim_;
  const HandSlots& hands_;
  SnapshotRing& ring_;
  LoopStatus& status_;
  const bool lockstep_;
  const double input_hold_;
  const int contact_every_;
  std::array<uint64_t, kMaxHands> consumed_version_{};
  double pending_since_ = -1.0;   // lockstep: when an input was first seen waiting
  int64_t last_snapshot_us_ = 0;  // wall time of the last state
  double last_step_s_ = 0.0;      // when the last step started (monotonic)
  double stall_from_ = -1.0, stall_s_ = 0.0;  // the latest stall: when it began, how long it lasted
  std::array<TimedInput, kMaxHands> latest_, older_;
  // Per slot, the input the last step that took one took (seq, client): where a late step goes on from.
  std::array<int64_t, kMaxHands> used_seq_{};
  std::array<int32_t, kMaxHands> used_client_{};
  static constexpr int kInOrderLookahead = 4;  // inputs lost on the way are skipped, up to this many
  HandInputs inputs_;
};

}  // namespace igms
