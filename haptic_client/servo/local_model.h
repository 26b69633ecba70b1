// The client's local model of the robot (a local proxy, as in remote dynamic
// proxies and Glencross et al.): while the user pushes or pulls, the robot
// the user feels is the newest server state carried forward through the
// client's own copy of the server's step (core Simulation: the hold
// controller, the coupling of eq. 3 / eq. 4, the scene's integrator) under
// the inputs the server has not applied yet. So the robot gives way to the
// hand at once, whatever the delay, and each new server state re-bases it.
// A scene of robots alone carries stretches without interaction kinematically
// (q + v h + qdd h^2/2): the trajectory the server follows after an edit is its own.
// A scene with free bodies runs its step between interactions as during them
// (bodies, contacts, the hand's proxy): a ball falling onto the table lands on it
// in the estimate too, instead of being carried into it for the round trip.
// Built once (allocates); run() does not allocate.
#pragma once

#include <cstdint>
#include <vector>

#include "core/simulation/simulation.h"
#include "haptic_client/servo/state_estimate.h"

namespace igms {

// The inputs a client sent, by seq, as the server's step takes them, and when
// each was sent (monotonic s: the round trip of the state that echoes it).
class SentInputs {
 public:
  static constexpr int64_t kCapacity = 4096;
  void put(int64_t seq, const InteractionInput& in, double sent_at = 0.0) {
    ring_[slot(seq)] = in;
    sent_at_[slot(seq)] = sent_at;
  }
  const InteractionInput& at(int64_t seq) const { return ring_[slot(seq)]; }
  double sentAt(int64_t seq) const { return sent_at_[slot(seq)]; }

 private:
  static size_t slot(int64_t seq) { return static_cast<size_t>(seq % kCapacity); }
  std::vector<InteractionInput> ring_ = std::vector<InteractionInput>(kCapacity);
  std::vector<double> sent_at_ = std::vector<double>(kCapacity, 0.0);
};

class LocalModel {
 public:
  // budget_us > 0: a run stops stepping once it has taken that long (µs of compute, checked after each
  // step) and carries the rest kinematically, so a stretch of dear steps (a solve at its sweep limit, a
  // slipping friction turned by Newton's method) costs the servo loop at most the budget and one step.
  LocalModel(const ResolvedScene& scene, int max_steps, double budget_us = 0.0);
  // How many of this scene's steps fit in budget_us, timed here (5 to 200).
  static int stepsWithin(const ResolvedScene& scene, double budget_us);

  // The robot after the inputs (from, to] (seqs) applied to `state`, one step
  // each (at most max_steps; beyond, carried kinematically). false when none
  // of them interacts in a scene without free bodies: then the caller's
  // kinematic prediction is as good. After a step whose contact solve ran to
  // its sweep limit (up to ~1 ms) it carries on kinematically: such a step
  // stays in the window for the round trip and would be paid every cycle.
  // velocities (optional): every link's velocity there, world axes.
  bool run(const RobotSample& state, const SentInputs& inputs, int64_t from, int64_t to, std::vector<SE3>& links,
           std::vector<Motion>* velocities = nullptr);
  int lastSteps() const { return last_steps_; }
  // Whether the last run stopped after a step whose contact solve ran to its sweep limit, and how many
  // runs did, since construction.
  bool lastCutShort() const { return last_cut_short_; }
  int64_t cutShort() const { return cut_short_; }
  // The deepest overlap of two things in contact at the start of any step this model took (m): how far
  // its estimate put a body inside another.
  double maxPenetration() const { return max_penetration_; }
  // Whether the last run stopped at its time budget, and how many runs did, since construction.
  bool lastOverBudget() const { return last_over_budget_; }
  int64_t overBudget() const { return over_budget_; }

 private:
  void kinematicStep(double h);

  Simulation sim_;
  const int max_steps_;
  const double budget_us_;
  const bool environment_;  // free bodies: every stretch is stepped
  double max_penetration_ = 0.0;
  VectorX q_, v_, qdd_, q_next_, v_mid_;
  int last_steps_ = 0;
  bool last_cut_short_ = false;
  int64_t cut_short_ = 0;
  bool last_over_budget_ = false;
  int64_t over_budget_ = 0;
};

}  // namespace igms
