// URDF position limits as a stiff, damped one-sided spring on each limited
// coordinate: beyond a limit by d, moving on into it at speed s, the joint
// takes tau = -(k d + b s) back toward its range, and never a pull toward the
// limit (a joint leaving faster than the spring pushes gets nothing). Inside
// the range it adds exactly nothing, so the dynamics away from the limits are
// unchanged.
//
// Gains per joint from its own inertia: k = w^2 / (H^-1)_ii and
// b = 2 w / (H^-1)_ii at the scene's initial configuration (clamped into the
// limits), so every joint, a 15 g finger or a shoulder, answers as a
// critically damped spring of w = 250 rad/s (1/w = 4 ms; w h = 0.25 at
// 1 kHz, inside what the explicit integrators take). Under a steady torque
// tau the joint sinks tau (H^-1)_ii / w^2 beyond its limit: light distal
// joints sink most (the 7-dof arm pulled at its flange: 16 mrad at 60 N,
// 58 mrad at 200 N). The one-sided damper lets a joint rebound with a little of its
// speed (about a tenth). The
// linearly-implicit scheme takes k and b implicitly, as it does joint damping.
// Velocity and effort limits are kept in the model, not applied.
#pragma once

#include <vector>

#include "core/model/data.h"
#include "core/model/model.h"

namespace igms {

class JointLimits {
 public:
  static constexpr double kOmega = 250.0;  // rad/s

  // Empty when `enabled` is false or no joint has finite limits.
  JointLimits(const Model& model, const VectorX& q_reference, bool enabled);

  bool empty() const { return joints_.empty(); }
  // Adds the limit torques at (q, v) to tau; k and b (per velocity coordinate, zero where no limit acts)
  // are what the implicit step takes.
  void apply(const VectorX& q, const VectorX& v, VectorX& tau, VectorX& k, VectorX& b) const;

 private:
  struct Joint {
    int q = 0, v = 0;
    double lower = 0.0, upper = 0.0, k = 0.0, b = 0.0;
  };
  std::vector<Joint> joints_;
};

}  // namespace igms
