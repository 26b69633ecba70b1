#include "server/loop/stepper.h"

#include "core/realtime/clock.h"

namespace igms {

bool Stepper::step() {
  const uint64_t version = input_.read(&latest_);
  if (version != consumed_version_) {
    consumed_version_ = version;
    ++status_.consumed_inputs;
  }
  const bool fresh = version > 0 && (lockstep_ || monotonicSeconds() - latest_.arrived <= input_hold_);
  // Stopped for over 20 ms since the last state (SIGSTOP, a starved machine): the same test a
  // re-simulation makes on the states' utime and step time.
  const int64_t start_us = wallMicros();
  if (last_snapshot_us_ > 0 && start_us - last_snapshot_us_ > Simulation::kStallGapUs) sim_.noteStall();
  const double t0 = monotonicSeconds();
  const bool ok = sim_.step(fresh ? &latest_.input : nullptr);
  const auto step_us = static_cast<int32_t>((monotonicSeconds() - t0) * 1e6);
  if (sim_.outcome().clamped) ++status_.forces_clamped;
  status_.resume_ramps = sim_.resumeRamps();
  ++status_.steps;
  snapshot(step_us);
  return ok;
}

void Stepper::snapshot(int32_t step_us) {
  last_snapshot_us_ = wallMicros();
  Snapshot* slot = ring_.beginWrite();
  if (!slot) {
    ++status_.ring_drops;
    return;
  }
  takeSnapshot(sim_, last_snapshot_us_, step_us, *slot);
  ring_.endWrite();
}

}  // namespace igms
