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

bool Stepper::step(bool late) {
  const double now = monotonicSeconds();
  // The loop stood (SIGSTOP, a starved machine): that time does not age the inputs that arrived before
  // it. A hand that leaned on something through the stall goes on acting, and its resume ramp starts
  // from what it gave (hand_track.h); the inputs queued meanwhile arrive fresh.
  if (last_step_s_ > 0.0 && now - last_step_s_ > 1e-6 * static_cast<double>(Simulation::kStallGapUs)) {
    stall_from_ = last_step_s_;
    stall_s_ = now - last_step_s_;
  }
  last_step_s_ = now;
  inputs_.clear();
  for (size_t k = 0; k < hands_.size(); ++k) {
    const uint64_t version = hands_[k].read(&latest_[k]);
    // A late step (realtime, catching up after a stall) takes the hand's inputs in the order it made
    // them, the next after the one it took last, while that is older than the newest: the newest
    // would pair a step with where the hand is now, not where it was at that step.
    const TimedInput* in = &latest_[k];
    if (late && !lockstep_ && version > 0 && latest_[k].input.client == used_client_[k]) {
      const int64_t newest = latest_[k].input.seq;
      for (int64_t seq = used_seq_[k] + 1; seq < newest && seq <= used_seq_[k] + kInOrderLookahead; ++seq) {
        if (hands_[k].readSeq(seq, &older_[k]) && older_[k].input.client == used_client_[k]) {
          in = &older_[k];
          break;
        }
      }
    }
    const bool newest = in == &latest_[k];
    const bool unconsumed = newest ? version != consumed_version_[k] : true;
    if (unconsumed) ++status_.consumed_inputs;
    if (newest && unconsumed) consumed_version_[k] = version;
    const double age = now - in->arrived - (in->arrived <= stall_from_ ? stall_s_ : 0.0);
    const bool acts = version > 0 && (lockstep_ ? unconsumed : age <= input_hold_);
    if (!acts) continue;
    inputs_.add(in->input);
    used_seq_[k] = in->input.seq;
    used_client_[k] = in->input.client;
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
