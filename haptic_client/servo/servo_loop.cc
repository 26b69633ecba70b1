#include "haptic_client/servo/servo_loop.h"

#include <sched.h>

#include <cmath>

#include "core/realtime/clock.h"
#include "core/realtime/deadline.h"

namespace igms {

ServoLoop::ServoLoop(const ResolvedScene& scene, HapticDevice& device, ClientBus& bus, StateEstimate& estimate,
                     std::vector<SE3>& links, ServoStats& stats, const ServoConfig& config)
    : config_(config), period_(1.0 / config.rate_hz), sim_dt_(scene.scene.dt),
      map_{scene.scene.workspace_scale, scene.scene.workspace_offset}, device_(device), limits_(device.limits()),
      bus_(bus), estimate_(estimate), links_(links), stats_(stats), interaction_(scene) {
  msg_.client_id = config.client_id;
  msg_.tip_radius = scene.scene.push.tip_radius;
}

double ServoLoop::run(const std::atomic<bool>& stop) {
  const double start = monotonicSeconds();
  PeriodicDeadline deadline(period_);
  for (int64_t k = 1; !stop; ++k) {
    const double t = static_cast<double>(k - 1) * period_;
    if ((config_.duration > 0 && t >= config_.duration) || (config_.duration <= 0 && device_.finished(t))) break;
    deadline.sleep();
    const double cycle_start = monotonicSeconds();
    const double jitter_us = std::abs(cycle_start - (start + t)) * 1e6;
    stats_.jitter.push(jitter_us);
    stats_.jitter_all.add(jitter_us);
    cycle(k, cycle_start);
    deadline.advance();
  }
  return monotonicSeconds() - start;
}

void ServoLoop::cycle(int64_t k, double cycle_start) {
  // 1. The device, mapped into the scene.
  const double t = static_cast<double>(k - 1) * period_;
  const DeviceReading reading = device_.read(t);
  const Vector3 tip = map_.toScene(reading.position);
  const Vector3 tip_velocity = map_.scale * reading.velocity;
  // 2. The input: pull while the button is held, push when the tip touches a link.
  interaction_.setAttachment(reading.attach_frame, reading.attach_point);
  interaction_.fillInput(tip, tip_velocity, reading.buttons, msg_);
  msg_.utime = wallMicros();
  msg_.seq = k;
  msg_.session_token = bus_.sessionToken();
  msg_.last_state_seq = estimate_.any() ? estimate_.newest().seq : -1;
  const double sent = monotonicSeconds();
  bus_.publishInput(msg_);
  stats_.mode = msg_.mode;
  // 3. This cycle's state, until the deadline; 4. the force.
  render(tip, tip_velocity, awaitState(k, cycle_start, sent));
  ++stats_.cycles;
}

// Takes the states that arrive until this cycle's reply or the deadline.
bool ServoLoop::awaitState(int64_t k, double cycle_start, double sent) {
  const double deadline = cycle_start + config_.deadline_us * 1e-6;
  for (;;) {
    ReceivedState* r = nullptr;
    if (bus_.states().take(&r)) {
      if (!estimate_.offer(r->sample)) ++stats_.late;
      if (r->sample.input_seq >= k) {
        const double rtt_us = (r->received - sent) * 1e6;
        stats_.rtt.push(rtt_us);
        stats_.rtt_all.add(rtt_us);
        return true;
      }
    }
    if (monotonicSeconds() >= deadline) return false;
    // Within the deadline window: yield rather than sleep (a sleep's wake-up
    // costs tens of microseconds on a VM), so the bus thread runs at once.
    sched_yield();
  }
}

void ServoLoop::render(const Vector3& tip, const Vector3& tip_velocity, bool on_time) {
  if (estimate_.any()) {
    // The reply to input k is the state one simulation step after the reply to k-1.
    expected_time_ = on_time ? estimate_.newest().sim_time : expected_time_ + sim_dt_;
    bool fallback = false;
    estimate_.estimate(expected_time_, links_, &fallback);
    if (fallback) ++stats_.fallbacks;
  }
  const bool resynced = on_time && consecutive_misses_ >= 3;
  if (on_time) {
    consecutive_misses_ = 0;
  } else {
    ++stats_.misses;
    stats_.max_consecutive = std::max<int64_t>(stats_.max_consecutive, ++consecutive_misses_);
  }
  const Vector3 on_user =
      estimate_.any() ? interaction_.userForce(links_, expected_time_, tip, tip_velocity) : Vector3::Zero();
  // Lost: no state for lost_ms; the force ramps down, and back up when states return.
  const double age_ms = static_cast<double>(consecutive_misses_) * period_ * 1e3;
  const bool lost = estimate_.any() && age_ms > config_.lost_ms;
  stats_.lost = lost;
  const Vector3 rendered = interaction_.render(on_user, lost, resynced, period_, limits_.max_force);
  device_.write(rendered);  // scene axes = device axes (the mapping scales positions only)
  stats_.max_force_step = interaction_.maxForceStep();
  stats_.force_scale = interaction_.forceScale();
  for (int i = 0; i < 3; ++i) stats_.force[i] = rendered[i];
  stats_.state_age_ms = age_ms;
}

}  // namespace igms
