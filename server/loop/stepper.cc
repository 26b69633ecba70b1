#include "server/loop/stepper.h"

#include "core/realtime/clock.h"

namespace igms {

bool Stepper::inputPending() const {
  for (size_t k = 0; k < hands_.size(); ++k)
    if (hands_[k].version() != consumed_version_[k]) return true;
  return false;
}

bool Stepper::lockstepReady() {
  if (!inputPending()) return false;
  const double now = monotonicSeconds();
  if (pending_since_ < 0.0) pending_since_ = now;
  if (now - pending_since_ >= kLockstepWaitS) return true;
  TimedInput in;
  for (size_t k = 0; k < hands_.size(); ++k) {
    const uint64_t version = hands_[k].read(&in);
    const bool taking_part = version > 0 && now - in.arrived <= kLockstepQuietS;
    if (taking_part && version == consumed_version_[k]) return false;  // wait for this client's input
  }
  return true;
}

bool Stepper::step() {
  const double now = monotonicSeconds();
  inputs_.clear();
  for (size_t k = 0; k < hands_.size(); ++k) {
    const uint64_t version = hands_[k].read(&latest_[k]);
    const bool unconsumed = version != consumed_version_[k];
    if (unconsumed) {
      consumed_version_[k] = version;
      ++status_.consumed_inputs;
    }
    const bool acts = version > 0 && (lockstep_ ? unconsumed : now - latest_[k].arrived <= input_hold_);
    if (acts) inputs_.add(latest_[k].input);
  }
  pending_since_ = -1.0;
  // Stopped for over 20 ms since the last state (SIGSTOP, a starved machine): the same test a
  // re-simulation makes on the states' utime and step time.
  const int64_t start_us = wallMicros();
  if (last_snapshot_us_ > 0 && start_us - last_snapshot_us_ > Simulation::kStallGapUs) sim_.noteStall();
  const double t0 = monotonicSeconds();
  const bool ok = sim_.step(inputs_);
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
  const bool contacts_due = contact_every_ > 0 && sim_.steps() % contact_every_ == 0;
  takeSnapshot(sim_, last_snapshot_us_, step_us, contacts_due, *slot);
  ring_.endWrite();
}

}  // namespace igms
