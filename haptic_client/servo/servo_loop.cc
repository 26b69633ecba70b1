#include "haptic_client/servo/servo_loop.h"

#include <sched.h>
#include <time.h>

#include <algorithm>
#include <cmath>

#include "core/realtime/clock.h"
#include "core/realtime/deadline.h"

namespace igms {

namespace {
constexpr long kRealtimeWaitNs = 50000;  // a real-time loop's pause between looks for its state
}  // namespace

ServoLoop::ServoLoop(const ResolvedScene& scene, HapticDevice& device, ClientBus& bus, StateEstimate& estimate,
                     std::vector<SE3>& links, ServoStats& stats, const ServoConfig& config, ServoRecord* record)
    : config_(config), period_(1.0 / config.rate_hz), sim_dt_(scene.scene.dt),
      render_limits_{device.limits().max_force, device.limits().max_force_step, config.passivity,
                     config.passivity_tolerance,
                     stiffnessScale(device.limits().max_stiffness, couplingStiffness(scene.scene))},
      device_limits_(device.limits()), map_{scene.scene.workspace_scale, scene.scene.workspace_offset}, device_(device),
      bus_(bus), estimate_(estimate), links_(links), stats_(stats), record_(record && record->on() ? record : nullptr),
      interaction_(scene) {
  link_velocities_.assign(links.size(), Motion::Zero());
  msg_.client_id = config.client_id;
  msg_.tip_radius = scene.scene.push.tip_radius;
  if (estimate.policy() == FallbackPolicy::Predict)
    local_ = std::make_unique<LocalModel>(scene, LocalModel::stepsWithin(scene, config.local_budget_us),
                                          config.local_budget_us);
}

double ServoLoop::run(const std::atomic<bool>& stop) {
  const int policy = sched_getscheduler(0);
  realtime_ = policy == SCHED_FIFO || policy == SCHED_RR;
  const double start = monotonicSeconds();
  PeriodicDeadline deadline(period_);
  for (int64_t k = 1; !stop; ++k) {
    const double t = static_cast<double>(k - 1) * period_;
    if ((config_.duration > 0 && t >= config_.duration) || (config_.duration <= 0 && device_.finished(t))) break;
    // The catch-up rule: a cycle that starts late runs at once and does not
    // wait for its reply beyond its own (passed) deadline, so a few late
    // cycles are made up back to back (compressed); more than 50 periods
    // behind, the missed periods are skipped, not replayed. Both counted.
    if (const int64_t skipped = deadline.skipIfBehind(50)) stats_.skipped_periods += skipped;
    const double nominal = deadline.at();
    deadline.sleep();
    const double cycle_start = monotonicSeconds();
    const double jitter_us = std::abs(cycle_start - nominal) * 1e6;
    if (cycle_start - nominal > period_) ++stats_.late_cycles;
    stats_.jitter.push(jitter_us);
    stats_.jitter_all.add(jitter_us);
    cycle(k, nominal);
    // Sharing a lockstep server with another hand: the step waits for both inputs, so a cycle that
    // starts too far ahead of the other client's gets its echo after its deadline. Shift this loop's
    // phase later (at most once in 50 cycles) so that it waits 100 us less than its deadline: the
    // client ahead stays ahead (no leapfrogging), the rate stays 1 kHz.
    if (phase_lag_ > 0.0 && k - last_phase_shift_ >= 50) {
      deadline.delay(phase_lag_ + 100e-6);
      ++stats_.phase_shifts;
      last_phase_shift_ = k;
    }
    phase_lag_ = 0.0;
    deadline.advance();
  }
  return monotonicSeconds() - start;
}

void ServoLoop::cycle(int64_t k, double nominal_start) {
  // 1. The device, mapped into the scene.
  const double t = static_cast<double>(k - 1) * period_;
  const double read_start = monotonicSeconds();
  const DeviceReading reading = device_.read(t);
  const double read_end = monotonicSeconds();
  stats_.device_read.add((read_end - read_start) * 1e6);
  if (read_end - read_start > config_.blocked_read_ms * 1e-3) {
    stats_.blocked_reads.fetch_add(1, std::memory_order_relaxed);
    blocked_until_ = read_end + std::max(read_end - read_start, config_.lost_ms * 1e-3);
  }
  const bool device_lost = reading.device_lost || read_end < blocked_until_;
  const Vector3 tip = map_.toScene(reading.position);
  const Vector3 tip_velocity = map_.scale * reading.velocity;
  // 2. The input: pull while the button is held, push when the tip touches a link.
  interaction_.setAttachment(reading.attach_frame, reading.attach_point);
  interaction_.setOrientation(reading.has_orientation, reading.orientation, reading.angular_velocity);
  interaction_.fillInput(tip, tip_velocity, reading.buttons, msg_);
  msg_.utime = wallMicros();
  msg_.seq = k;
  msg_.session_token = bus_.sessionToken();
  msg_.last_state_seq = estimate_.any() ? estimate_.newest().seq : -1;
  const double sent_at = monotonicSeconds();
  bus_.publishInput(msg_);
  InteractionInput sent = interaction_.input();
  sent.seq = k;
  sent.client = config_.client_id;
  sent_inputs_.put(k, sent, sent_at);
  stats_.mode = msg_.mode;
  // 3. The states; 4. the force.
  render(k, tip, tip_velocity, awaitState(k, nominal_start), device_lost);
  ++stats_.cycles;
}

// One state from the bus: into the estimate if newer, and its round trip if it echoes one of our inputs.
void ServoLoop::take(const ReceivedState& r) {
  const double previous = estimate_.any() ? estimate_.newestReceived() : r.received;
  if (!estimate_.offer(r.sample, r.received)) {
    ++stats_.late;
    return;
  }
  // Back after a gap in arrivals: the force moves to its new value over a few cycles.
  if (r.received - previous > 3.0 * period_) resync_ = true;
  const int64_t echoed = r.sample.input_seq;
  if (r.sample.input_client != config_.client_id || echoed < 1 || echoed <= msg_.seq - SentInputs::kCapacity)
    return;
  const double rtt = r.received - sent_inputs_.sentAt(echoed);
  if (rtt < 0.0) return;
  const double late = rtt - config_.deadline_us * 1e-6;
  if (r.sample.nconsumed >= 2 && late > 0.0 && rtt < period_) phase_lag_ = std::max(phase_lag_, late);
  stats_.rtt.push(rtt * 1e6);
  stats_.rtt_all.add(rtt * 1e6);
  if (r.received - rtt_window_start_ > 0.5) {
    rtt_min_before_ = rtt_min_now_;
    rtt_min_now_ = 1e9;
    rtt_window_start_ = r.received;
  }
  rtt_min_now_ = std::min(rtt_min_now_, rtt);
}

// Half the smallest round trip of the last 0.5-1 s (0 before any echo).
double ServoLoop::oneWayDelay() const {
  const double m = std::min(rtt_min_now_, rtt_min_before_);
  return m < 1e8 ? 0.5 * m : 0.0;
}

// Takes the states that arrive. While echoes come back within the deadline,
// waits for this cycle's until the deadline (from the cycle's nominal start,
// not a late actual one); otherwise (a far server, or a realtime one whose
// reply this cycle's input cannot hurry) goes on with the newest.
bool ServoLoop::awaitState(int64_t k, double nominal_start) {
  const double deadline = nominal_start + config_.deadline_us * 1e-6;
  const bool wait = 2.0 * oneWayDelay() < config_.deadline_us * 1e-6;
  bool echoed = false;
  for (;;) {
    ReceivedState* r = nullptr;
    if (bus_.states().take(&r)) {
      take(*r);
      echoed |= r->sample.input_client == config_.client_id && r->sample.input_seq >= k;
      if (echoed) return true;
    }
    if (!wait || monotonicSeconds() >= deadline) return echoed;
    // Within the deadline window: yield rather than sleep (a sleep's wake-up
    // costs tens of microseconds on a VM), so the bus thread runs at once.
    // Under real-time scheduling a yield passes the core to no ordinary
    // thread: the loop would hold it up to the deadline every cycle, starve
    // the bus thread that brings the state it waits for, and run into the
    // kernel's real-time throttling (tens of ms without a cycle). Sleep a
    // little instead.
    if (realtime_) {
      const timespec pause{0, kRealtimeWaitNs};
      clock_nanosleep(CLOCK_MONOTONIC, 0, &pause, nullptr);
    } else {
      sched_yield();
    }
  }
}

double ServoLoop::estimateRobot(int64_t k, double age, bool on_time) {
  const RobotSample& newest = estimate_.newest();
  // The inputs the newest state has not seen: those after the one it echoes.
  const bool echoes = newest.input_client == config_.client_id && newest.input_seq >= 1 && newest.input_seq <= k &&
                      k - newest.input_seq < SentInputs::kCapacity;
  const double horizon = echoes ? static_cast<double>(k - newest.input_seq) * sim_dt_ : age;
  estimate_time_ = newest.sim_time + horizon;
  if (local_ && echoes && local_->run(newest, sent_inputs_, newest.input_seq, k, links_, &link_velocities_)) {
    stats_.local_steps = local_->lastSteps();
    stats_.local_runs.fetch_add(1, std::memory_order_relaxed);
    stats_.local_max_penetration = local_->maxPenetration();
    stats_.local_cut_short = local_->cutShort();
    stats_.local_over_budget = local_->overBudget();
    if (!on_time) ++stats_.fallbacks;
    return horizon;
  }
  bool fallback = false;
  estimate_.estimate(estimate_time_, links_, &fallback, &link_velocities_);
  if (fallback && !on_time) ++stats_.fallbacks;  // rendered without this cycle's reply
  return horizon;
}

void ServoLoop::render(int64_t k, const Vector3& tip, const Vector3& tip_velocity, bool on_time, bool device_lost) {
  const double now = monotonicSeconds();
  double age_ms = 0.0;
  if (estimate_.any()) {
    // The newest state's age: since it arrived, plus the way it came.
    const double age = now - estimate_.newestReceived() + oneWayDelay();
    age_ms = age * 1e3;
    stats_.age_us.push(age * 1e6);
    stats_.age_all.add(age * 1e6);
    stats_.prediction_ms = estimateRobot(k, age, on_time) * 1e3;
  }
  if (on_time) {
    consecutive_misses_ = 0;
  } else {
    ++stats_.misses;
    stats_.max_consecutive = std::max<int64_t>(stats_.max_consecutive, ++consecutive_misses_);
  }
  // Lost: no new state for lost_ms; the force ramps down, and back up when states return.
  const bool server_lost = estimate_.any() && (now - estimate_.newestReceived()) * 1e3 > config_.lost_ms;
  stats_.lost = server_lost;
  stats_.device_lost = device_lost;
  const bool lost = server_lost || device_lost;
  if (lost) interaction_.disengagePush();
  const Vector3 on_user =
      estimate_.any() ? interaction_.userForce(links_, estimate_time_, tip, tip_velocity,
                                               estimate_.hasModel() ? &link_velocities_ : nullptr)
                      : Vector3::Zero();
  const Vector3 rendered = interaction_.render(on_user, tip_velocity, lost, resync_, period_, render_limits_);
  resync_ = false;
  const Vector3 torque = interaction_.renderTorque(interaction_.userTorque(), period_, device_limits_.max_torque,
                                                   device_limits_.max_torque_step, render_limits_.passivity);
  const double write_start = monotonicSeconds();
  device_.write(rendered);  // scene axes = device axes (the mapping scales positions only)
  if (device_limits_.max_torque > 0.0) device_.writeTorque(torque);
  stats_.device_write.add((monotonicSeconds() - write_start) * 1e6);
  for (int i = 0; i < 3; ++i) stats_.torque[i] = torque[i];
  stats_.max_force_step = interaction_.maxForceStep();
  stats_.slew_limited = interaction_.slewLimited();
  stats_.passivity_acted = interaction_.passivity().acted();
  stats_.proxy_substep_limited = interaction_.proxy().substepLimited();
  stats_.passivity_dissipated = interaction_.passivity().dissipated();
  stats_.passivity_min_energy = interaction_.passivity().minEnergy();
  stats_.force_scale = interaction_.forceScale();
  for (int i = 0; i < 3; ++i) stats_.force[i] = rendered[i];
  stats_.state_age_ms = age_ms;
  if (record_)
    record_->add(ServoRecordRow{static_cast<double>(k - 1) * period_, estimate_time_, msg_.mode, tip,
                                interaction_.proxy().position(), on_user, rendered});
}

}  // namespace igms
