// What stands between the computed force and the user's hand.
//  - StartupGuard: forces stay off until the commanded force is first small
//    (as CHAI3D does), so no spike hits a hand that starts inside a link.
//  - LossRamp: when the server is lost the force ramps down to zero, and back
//    up when it returns, never as a step.
//  - ResyncBlend: when states return after several missed cycles, the estimate
//    jumps to the true state; the force moves to its new value over a few
//    cycles instead of in one step.
//  - PassivityController: the time-domain passivity observer and controller
//    at the device port, so that no delay, prediction or re-basing hands the
//    user energy the user did not put in.
//  - The device's stable stiffness scales what the hand feels (stiffnessScale);
//    its limits clamp the force; then the per-cycle bound.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

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

// Time-domain passivity (Hannaford and Ryu 2002) at the device port. The
// observer sums the energy the user has put into the rest of the loop,
// E = sum of -f.v dt (f: the force on the user, v: the tip's velocity): the
// loop is passive while E >= 0. The robot may hand back kinetic energy it
// had from its own controller when the contact began, so E may dip a little
// by physics alone; below -tolerance (energy made by delay, prediction error
// or a re-based estimate), the controller adds damping along v, at most
// max_damping and at most max_force, until E is back at -tolerance (what it
// cannot take out this cycle it takes out in the next ones). E restarts with each
// interaction (a long positive balance would otherwise hide a later active
// stretch).
class PassivityController {
 public:
  explicit PassivityController(double tolerance_J = 0.025, double max_damping = 30.0, double max_force = 1.0)
      : tolerance_(tolerance_J), max_damping_(max_damping), max_force_(max_force) {}
  Vector3 apply(const Vector3& f, const Vector3& v, double dt) {
    const double v2 = v.squaredNorm();
    const double e = energy_ - f.dot(v) * dt + tolerance_;
    if (e >= 0.0 || v2 < 1e-12) return f;
    ++acted_;
    // -(f - a v).v dt = -f.v dt + a v2 dt: a = -e / (v2 dt) brings E back to -tolerance.
    const double a = std::min({-e / (v2 * dt), max_damping_, max_force_ / std::sqrt(v2)});
    dissipated_ += a * v2 * dt;
    return f - a * v;
  }
  // What was rendered this cycle enters the balance.
  void commit(const Vector3& rendered, const Vector3& v, double dt) {
    energy_ -= rendered.dot(v) * dt;
    min_energy_ = std::min(min_energy_, energy_);
  }
  void restart() { energy_ = 0.0; }
  void setTolerance(double joules) { tolerance_ = joules; }
  double energy() const { return energy_; }
  double minEnergy() const { return min_energy_; }  // the lowest balance of any interaction, J
  int64_t acted() const { return acted_; }
  double dissipated() const { return dissipated_; }

 private:
  double tolerance_, max_damping_, max_force_;
  double energy_ = 0.0, min_energy_ = 0.0;
  int64_t acted_ = 0;
  double dissipated_ = 0.0;
};

// What may reach the hand: the device's largest force, the largest change a
// cycle, and whether the passivity controller runs.
struct RenderLimits {
  double max_force = 1e9;
  double max_step = 1e9;
  bool passivity = false;  // false: the observer still sums E, the controller does nothing
  double passivity_tolerance = 0.025;  // J
  // The hand feels this share of the coupling's force (stiffnessScale); the robot gets all of it.
  double stiffness_scale = 1.0;
};

// The share of the coupling's force a device can render stably: a spring of `coupling` N/m at
// the device (the scene's stiffest spring times the workspace scale: a device's metre is that
// many scene metres) above the device's stable stiffness is felt scaled down to it, as CHAI3D
// caps a tool's stiffness at the device's. An unlimited device (infinity: a simulated one) feels it all.
inline double stiffnessScale(double device_stiffness, double coupling) {
  return std::isfinite(device_stiffness) && device_stiffness > 0 && coupling > device_stiffness
             ? device_stiffness / coupling
             : 1.0;
}

inline Vector3 clampMagnitude(const Vector3& f, double max) {
  const double n = f.norm();
  return n > max ? Vector3(f * (max / n)) : f;
}

}  // namespace igms
