// One word for a hand, as the step sees it: the validated input each hand
// sends (InteractionInput, scene coordinates, link names already resolved to
// frames at the bus edge), the inputs one step consumes (HandInputs), the
// force a hand applies (HandForce: the dynamics evaluate it, the step reports
// it) and what the step did with each (HandOutcome, StepOutcome). The server's
// hand slots and the client include this, not the whole simulation.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>

#include "core/model/spatial.h"

namespace igms {

enum class InteractionMode : int8_t { None = 0, Push = 1, Pull = 2 };

// Hands acting on the robot in one step, at most (one coupling each).
constexpr int kMaxHands = 4;

// One validated haptic input, in scene coordinates. A push acts where the server's proxy for this
// hand rests (Simulation::coupleHands): the link the client names is validated at the bus edge, not used.
struct InteractionInput {
  InteractionMode mode = InteractionMode::None;
  Vector3 tip_position = Vector3::Zero();
  Vector3 tip_velocity = Vector3::Zero();
  double tip_radius = 0.01;
  int attach_frame = -1;   // pull: the attachment link (-1: the scene's)
  Vector3 attach_point = Vector3::Zero();
  // A 6-dof device: its orientation (world <- tip) and angular velocity, and
  // the grasped frame in the attachment link (link <- grasp; the client sets it
  // when the grab starts so that the rotational spring starts relaxed).
  bool has_orientation = false;
  Eigen::Quaterniond tip_orientation = Eigen::Quaterniond::Identity();
  Vector3 tip_angular_velocity = Vector3::Zero();
  Eigen::Quaterniond attach_orientation = Eigen::Quaterniond::Identity();
  int64_t seq = -1;
  int32_t client = -1;
};

// The inputs one step consumes: at most one per client. The step takes them
// in client-id order whatever the order here, so a re-simulation that hands
// over the same set reproduces the step bit for bit.
struct HandInputs {
  std::array<InteractionInput, kMaxHands> in;
  int n = 0;
  void clear() { n = 0; }
  // false when kMaxHands inputs are already here.
  bool add(const InteractionInput& input) {
    if (n >= kMaxHands) return false;
    in[static_cast<size_t>(n++)] = input;
    return true;
  }
};

// The force one hand applies to what it acts on. The dynamics evaluate it (CouplingForce adds its
// linearisation), and the step reports the one it applied (HandOutcome): one type for both.
struct HandForce {
  Vector3 force = Vector3::Zero();   // on the robot or body, world, N (the hand feels its reaction)
  Vector3 torque = Vector3::Zero();  // on it, world, N m: the 6-D pull's moment
  Vector3 point = Vector3::Zero();   // where the force acts, world
  bool clamped = false;              // |F| or |torque| limited to the scene's maximum
};

// One hand's part of a step: the input it consumed and the force it applied.
struct HandOutcome {
  int32_t client = -1;
  int64_t input_seq = -1;
  InteractionMode mode = InteractionMode::None;  // None: the input did not interact (or its mode is off)
  HandForce applied;                             // zero while it touches nothing
};

// What the last step did, for the state message: the users' forces the step
// applied. For the explicit schemes that is their value at the step's start
// state; the linearly-implicit step takes the springs at its end, and reports
// those (CoupledDynamics::appliedCouplings): what moved the robot or the body.
struct StepSummary {
  InteractionMode mode = InteractionMode::None;  // the first interacting hand's (in client order)
  Vector3 force_on_robot = Vector3::Zero();      // world, N: the sum over the hands
  Vector3 torque_on_robot = Vector3::Zero();     // world, N m: the sum of the hands' moments
  Vector3 force_point = Vector3::Zero();         // the first interacting hand's point, world
  bool clamped = false;                          // some hand's force or torque was limited
  bool replanned = false;                        // a resume trajectory started this step
  int64_t input_seq = -1;                        // the first consumed input (hands[] lists them all)
  int32_t input_client = -1;
};

struct StepOutcome : StepSummary {
  std::array<HandOutcome, kMaxHands> hands;  // every consumed input, in client-id order: the first nhands
  int nhands = 0;
  // A new step's: the summary as constructed and no hands. The entries of hands[] are left as they
  // are (only the first nhands are read, and the step sets each whole as it adds it): the step then
  // does not rewrite the whole array, 0.4 kB, every millisecond.
  void restart() {
    static_cast<StepSummary&>(*this) = StepSummary{};
    nhands = 0;
  }
};

}  // namespace igms
