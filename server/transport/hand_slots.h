// The newest admitted input of each hand: one lock-free slot per client, so
// that two people interacting at once each have their own coupling (and
// their own hold time) instead of taking turns step by step. The bus side
// seats a client in a slot; the step reads every slot without a lock.
#pragma once

#include <array>

#include "core/realtime/latest_value.h"
#include "core/simulation/hand_input.h"

namespace igms {

// An admitted input, with the time it arrived.
struct TimedInput {
  InteractionInput input;
  double arrived = 0.0;  // monotonic s
};

using HandSlots = std::array<LatestValue<TimedInput>, kMaxHands>;

}  // namespace igms
