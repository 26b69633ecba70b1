// How the web device's tip follows the mouse: the page sends targets at
// display rate (about 60 Hz, in steps of centimetres); the servo loop reads
// the tip at 1 kHz. A critically damped second-order filter with bounded
// acceleration and speed turns the steps into a smooth path, so the push
// force (k_p times the penetration) and the pull's damper (b times the tip's
// velocity) change little from one cycle to the next. A drag starts with a
// jump to the picked point; a released push backs out the way it came until
// nothing pushes back; then the tip waits, parked, out of the robot's way.
#pragma once

#include <cstdint>

#include "core/model/spatial.h"

namespace igms {

class MouseFollower {
 public:
  // The mouse target the page last sent (scene coordinates).
  struct Target {
    Vector3 tip = Vector3::Zero();
    bool active = false;  // a drag is on (false: back out if pushing, then park)
    bool pull = false;    // the modifier-drag: the spring of eq. 4
    // The drag's start (the page's "jump" message): the tip moves there at once. Kept in every later
    // target of the drag, so a busy machine that hands the loop only the newest target loses no start.
    int64_t drag_seq = 0;  // the seq of the jump that started this drag
    Vector3 drag_start = Vector3::Zero();
    int attach_frame = -1;
    Vector3 attach_point = Vector3::Zero();
    Vector3 rotation = Vector3::Zero();  // pull: the grabbed frame's turn since the grab (rotation vector, world)
    int64_t seq = 0;
  };

  static constexpr double kOmega = 40.0;      // rad/s, the filter's natural frequency
  static constexpr double kMaxSpeed = 0.25;   // m/s: k_p v dt = 0.5 N a cycle at k_p = 2000 N/m
  static constexpr double kMaxAccel = 4.0;    // m/s^2: b dv = 0.08 N a cycle at b = 20 N s/m
  static constexpr double kReleased = 0.05;   // N: a released push has backed out
  static constexpr double kBackOut = 0.05;    // m past the drag's start, at most

  explicit MouseFollower(const Vector3& parked) : parked_(parked), x_(parked), retract_(parked), exit_(parked) {}

  // One servo cycle of dt seconds toward `target`; `rendered` is the force
  // the device rendered last cycle. Returns the tip.
  const Vector3& update(const Target& target, double dt, const Vector3& rendered);

  const Vector3& position() const { return x_; }
  const Vector3& velocity() const { return v_; }
  bool parked() const { return parked_now_; }

 private:
  const Vector3 parked_;
  Vector3 x_, v_ = Vector3::Zero();
  Vector3 retract_;  // where the drag began
  Vector3 exit_;     // a released push backs out toward this
  bool backing_out_ = false, was_active_ = false, parked_now_ = true;
  int64_t last_drag_seq_ = 0;
};

}  // namespace igms
