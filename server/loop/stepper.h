// The step of the server's loop: the newest admitted input, one simulation
// step, timed, and its snapshot into the ring for the publisher. Realtime: an
// input keeps acting for input_hold after it arrived (the client may miss a
// cycle); lockstep: each input drives exactly one step. Allocation-free.
#pragma once

#include "core/realtime/latest_value.h"
#include "core/simulation/simulation.h"
#include "server/loop/loop_status.h"
#include "server/loop/snapshot.h"
#include "server/transport/bus_receiver.h"

namespace igms {

class Stepper {
 public:
  Stepper(Simulation& sim, const LatestValue<TimedInput>& input, SnapshotRing& ring, LoopStatus& status, bool lockstep,
          double input_hold_s)
      : sim_(sim), input_(input), ring_(ring), status_(status), lockstep_(lockstep), input_hold_(input_hold_s) {}

  // An input arrived that no step has consumed yet.
  bool inputPending() const { return input_.version() != consumed_version_; }
  // One step. \return false when the simulation diverged (its report says why).
  bool step();
  // The current state into the ring (the initial state; after each step).
  void snapshot(int32_t step_us);

 private:
  Simulation& sim_;
  const LatestValue<TimedInput>& input_;
  SnapshotRing& ring_;
  LoopStatus& status_;
  const bool lockstep_;
  const double input_hold_;
  uint64_t consumed_version_ = 0;
  int64_t last_snapshot_us_ = 0;  // wall time of the last state
  TimedInput latest_;
};

}  // namespace igms
