// The newest admitted input of each hand: one lock-free slot per client, so
// that two people interacting at once each have their own coupling (and
// their own hold time) instead of taking turns step by step. The bus side
// seats a client in a slot; the step reads every slot without a lock.
#pragma once

#include <array>

#include "core/realtime/latest_value.h"
#include "core/realtime/seq_history.h"
#include "core/simulation/hand_input.h"

namespace igms {

// An admitted input, with the time it arrived.
struct TimedInput {
  InteractionInput input;
  double arrived = 0.0;  // monotonic s
};

// One hand's slot: its newest admitted input, and its last kHistory by seq, so that a step that runs
// late (catching up after a stall) can take them in the order the hand made them.
class HandSlot {
 public:
  static constexpr int kHistory = 64;
  // The history first: a reader that sees the newest finds it there too.
  void write(const TimedInput& in) {
    history_.write(in.input.seq, in);
    latest_.write(in);
  }
  // Copies the newest into *out. \return its version (0: never written).
  uint64_t read(TimedInput* out) const { return latest_.read(out); }
  uint64_t version() const { return latest_.version(); }
  // The input this slot's client sent with `seq` (false: not admitted here, or kHistory or more ago).
  bool readSeq(int64_t seq, TimedInput* out) const { return history_.read(seq, out); }

 private:
  SeqHistory<TimedInput, kHistory> history_;
  LatestValue<TimedInput> latest_;
};

using HandSlots = std::array<HandSlot, kMaxHands>;

}  // namespace igms
