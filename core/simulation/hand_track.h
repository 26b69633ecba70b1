// One hand as the step sees it across steps: which client it is, the resume
// ramp that brings its coupling back in after a gap (simulation.h has the
// rule) from the force it gave before the gap, the robot it holds, and its
// tip's proxy against the exact state. The simulation keeps
// kMaxHands of them and gives a new client the one quiet for longest.
#pragma once

#include <algorithm>
#include <cstdint>

#include "core/interaction/proxy.h"

namespace igms {

class HandTrack {
 public:
  static constexpr int kResumeGapSteps = 20;      // steps without any input: a gap
  static constexpr int64_t kResumeSeqJump = 100;  // a client's seq jumping this far: a gap (jitter stays below)
  static constexpr double kResumeRamp = 0.1;      // s to bring the coupling back in after a gap

  // A new hand, or a re-based copy that does not know the server's gaps (the proxy is left as it is).
  void restart(int32_t id) {
    client_ = id;
    last_seq_ = -1;
    steps_without_input_ = 0;
    stall_ = false;
    scale_ = 1.0;
    gave_ = gave_before_ = carried_ = Given{};
  }
  // One step passes, with or without an input from this hand: its ramp runs on, and it holds nothing
  // until its input this step says what (holdRobot).
  void tick(double dt) {
    if (scale_ < 1.0) scale_ = std::min(1.0, scale_ + dt / kResumeRamp);
    ++steps_without_input_;
    held_before_ = held_;
    held_ = -1;
    gave_before_ = gave_;
    gave_ = Given{};
  }
  // This step's push or pull acts on robot `robot` (-1: on none of them: a push that touches nothing,
  // a pull on a free body). A hand that goes on pushing holds the robot it held, so a push that
  // slides off for a step does not let the robot go. \return the robot it holds (-1: none).
  int holdRobot(int robot) {
    held_ = robot >= 0 ? robot : held_before_;
    return held_;
  }
  // Lets go of what it held (a reset).
  void letGo() { held_ = held_before_ = -1; }
  // This hand's input `seq` is taken; `interacts`: it pushes or pulls. After a gap (steps without
  // its input, its seq jumping, or a stall of the loop; not before its first input) an interacting
  // input restarts the ramp, this step its first. \return whether it did.
  bool take(int64_t seq, bool interacts, double dt) {
    const bool gap = stall_ || (last_seq_ >= 0 && (steps_without_input_ > kResumeGapSteps ||
                                                   seq - last_seq_ > kResumeSeqJump));
    const bool ramp = interacts && gap;
    if (ramp) {
      scale_ = dt / kResumeRamp;
      carried_ = gave_before_;  // what it gave the step before the gap (nothing when it was away)
    }
    // A stall waits for the hand's next input: the first steps after one often have none fresh
    // (the last arrived before the stop), and the queued inputs that follow run on in seq.
    stall_ = false;
    last_seq_ = seq;
    steps_without_input_ = 0;
    return ramp;
  }
  // The loop stopped: the next interacting input ramps in.
  void noteStall() { stall_ = true; }

  // What this hand gave this step (its coupling's frame and the sizes of its force and torque), for a
  // ramp that may follow a gap.
  void gave(int frame, double force, double torque) { gave_ = Given{frame, force, torque}; }
  // The ramp's floor: the sizes of the force and torque the hand gave on `frame` the step before its
  // gap (0 when it gave nothing there). A hand that leaned on something through a stall of the loop
  // goes on giving that much: only what it adds comes back over the ramp.
  double carriedForce(int frame) const { return carried_.frame == frame ? carried_.force : 0.0; }
  double carriedTorque(int frame) const { return carried_.frame == frame ? carried_.torque : 0.0; }

  int32_t client() const { return client_; }
  int stepsWithoutInput() const { return steps_without_input_; }
  double scale() const { return scale_; }  // the coupling's share this step, (0, 1]

 private:
  // First, as the step reads them for every hand (the proxy's buffers follow).
  int32_t client_ = -1;
  int64_t last_seq_ = -1;
  int steps_without_input_ = 0;
  bool stall_ = false;
  double scale_ = 1.0;
  int held_ = -1, held_before_ = -1;  // the robot this hand holds (this step, the last)
  struct Given {
    int frame = -1;  // -1: it gave nothing
    double force = 0.0, torque = 0.0;
  };
  Given gave_, gave_before_, carried_;  // this step's, the last step's, the one before the gap

 public:
  Proxy proxy;  // this hand's tip against the exact state (its buffers outlive restart())
};

}  // namespace igms
