#include "haptic_client/device/mouse_follower.h"

namespace igms {

const Vector3& MouseFollower::update(const Target& target, double dt, const Vector3& rendered) {
  Vector3 goal = target.tip;
  if (target.active) {
    if (target.drag_seq != last_drag_seq_) {
      x_ = retract_ = target.drag_start;
      v_.setZero();
      last_drag_seq_ = target.drag_seq;
    }
    // A released pull needs no way out: the client blends the spring off.
    backing_out_ = !target.pull;
  } else {
    if (was_active_) {
      // The way out: toward the drag's start and on past it, so the push's
      // force fades instead of vanishing in one cycle.
      const Vector3 out = retract_ - x_;
      const double n = out.norm();
      exit_ = n > 1e-6 ? Vector3(retract_ + out / n * kBackOut) : Vector3(x_ + Vector3(0.0, 0.0, kBackOut));
    }
    goal = exit_;
    if (backing_out_ && (rendered.norm() < kReleased || (x_ - exit_).norm() < 1e-3)) backing_out_ = false;
    if (!backing_out_) {
      goal = x_ = parked_;
      v_.setZero();
    }
  }
  if (dt > 0 && (target.active || backing_out_)) {
    Vector3 a = kOmega * kOmega * (goal - x_) - 2.0 * kOmega * v_;
    const double accel = a.norm();
    if (accel > kMaxAccel) a *= kMaxAccel / accel;
    v_ += a * dt;
    const double speed = v_.norm();
    if (speed > kMaxSpeed) v_ *= kMaxSpeed / speed;
    x_ += v_ * dt;
  }
  was_active_ = target.active;
  parked_now_ = !target.active && !backing_out_;
  return x_;
}

}  // namespace igms
