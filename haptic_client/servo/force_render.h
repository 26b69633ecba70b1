// What stands between the computed force and the user's hand.
//  - StartupGuard: forces stay off until the commanded force is first small
//    (as CHAI3D does), so no spike hits a hand that starts inside a link.
//  - LossRamp: when the server is lost the force ramps down to zero, and back
//    up when it returns, never as a step.
//  - ResyncBlend: when states return after several missed cycles, the estimate
//    jumps to the true state; the force moves to its new value over a few
//    cycles instead of in one step.
//  - The device's limits clamp the force last.
#pragma once

#include <algorithm>

#include "core/model/spatial.h"

namespace igms {

class StartupGuard {
 public:
  explicit StartupGuard(double threshold_N = 0.5) : threshold_(threshold_N) {}
  Vector3 apply(const Vector3& f) {
    if (!armed_ && f.norm() < threshold_) armed_ = true;
    return armed_ ? f : Vector3::Zero();
  }
  bool armed() const { return armed_; }

 private:
  double threshold_;
  bool armed_ = false;
};

class LossRamp {
 public:
  // seconds for a full ramp down or up.
  explicit LossRamp(double ramp_s = 0.1) : rate_(1.0 / ramp_s) {}
  // Called each cycle of dt seconds; lost: no state for the loss timeout.
  double update(bool lost, double dt) {
    scale_ = std::clamp(scale_ + (lost ? -rate_ : rate_) * dt, 0.0, 1.0);
    return scale_;
  }
  double scale() const { return scale_; }

 private:
  double rate_;
  double scale_ = 1.0;
};

class ResyncBlend {
 public:
  void resync(int cycles) { left_ = cycles; }
  Vector3 apply(const Vector3& target, const Vector3& last) {
    if (left_ <= 0) return target;
    const Vector3 out = last + (target - last) / static_cast<double>(left_);
    --left_;
    return out;
  }

 private:
  int left_ = 0;
};

inline Vector3 clampMagnitude(const Vector3& f, double max) {
  const double n = f.norm();
  return n > max ? Vector3(f * (max / n)) : f;
}

}  // namespace igms
