#include "haptic_client/device/bus_device.h"

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "bus/message_signature.h"
#include "core/realtime/clock.h"

namespace igms {
namespace {

bool finiteWithin(const double* v, int n, double bound) {
  double sq = 0.0;
  for (int k = 0; k < n; ++k) {
    if (!std::isfinite(v[k])) return false;
    sq += v[k] * v[k];
  }
  return std::sqrt(sq) <= bound;
}

bool validName(const std::string& s) {
  if (s.empty() || s.size() > 64) return false;
  for (char c : s)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

}  // namespace

BusDevice::BusDevice(const std::string& args, const DeviceContext& context)
    : base_(args.empty() ? "IGMS_DEVICE" : args),
      reading_channel_(base_ + "_READING"),
      force_channel_(base_ + "_FORCE"),
      lcm_(context.lcm_url),
      verifier_(context.key, "igms-haptic (device)"),
      publisher_(lcm_, context.key, 1024) {
  verifier_.pinSender({reading_channel_});  // the device that speaks first is the device: no second signer for it
  if (context.accept_replay) verifier_.acceptReplays();
  if (!validName(base_))
    throw std::runtime_error("--device lcm:NAME: NAME is a channel base (letters, digits, '_'), not '" + base_ + "'");
  if (!lcm_.good()) throw std::runtime_error("--device lcm: cannot open LCM at " + context.lcm_url);
  buffer_.resize(static_cast<size_t>(force_msg_.getEncodedSize()) + bus::kTrailerBytes);
  readings_ = bus::subscribe<device_reading_t>(
      lcm_, verifier_, reading_channel_, [this](const device_reading_t& m, const bus::Verdict&) { onReading(m); }, 64,
      [this](const bus::Verdict&) { ++refused_[kUndecodable]; });
  thread_ = std::thread([this] { receive(); });
  // The first reading brings the device's limits; the loop must not start without them.
  std::fprintf(stderr, "igms-haptic: waiting for the device's readings on %s\n", reading_channel_.c_str());
  const double t0 = monotonicSeconds();
  while (newest_.version() == 0 && monotonicSeconds() - t0 < kFirstReadingS)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  if (newest_.version() == 0) {
    stop_ = true;
    thread_.join();
    throw std::runtime_error("--device lcm:" + base_ + ": no valid reading on " + reading_channel_ + " within " +
                             std::to_string(static_cast<int>(kFirstReadingS)) + " s (" +
                             std::to_string(readingsRejected()) + " refused; messages: " + verifier_.summary() + ")");
  }
}

BusDevice::~BusDevice() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void BusDevice::receive() {
  while (!stop_) lcm_.handleTimeout(5);
}

void BusDevice::onReading(const device_reading_t& m) {
  const bool oriented = m.has_orientation;
  const double qn = std::sqrt(m.orientation[0] * m.orientation[0] + m.orientation[1] * m.orientation[1] +
                              m.orientation[2] * m.orientation[2] + m.orientation[3] * m.orientation[3]);
  if (!finiteWithin(m.position, 3, kMaxPosition) || !finiteWithin(m.velocity, 3, kMaxVelocity) ||
      (oriented && (!finiteWithin(m.angular_velocity, 3, kMaxAngularVelocity) || !(std::abs(qn - 1.0) <= 0.1))) ||
      m.buttons < 0 || m.buttons > 255 || !std::isfinite(m.max_force) || !std::isfinite(m.max_stiffness)) {
    ++refused_[kOutOfRange];
    return;
  }
  if (m.seq <= newest_seq_) {  // late, repeated or replayed: never steps the tip back
    ++refused_[kOutOfOrder];
    return;
  }
  newest_seq_ = m.seq;
  if (accepted_.load(std::memory_order_relaxed) == 0) {  // the device's limits, from its first reading
    if (m.max_force > 0) limits_.max_force = m.max_force;
    if (m.max_stiffness > 0) limits_.max_stiffness = m.max_stiffness;
  }
  Taken t;
  t.seq = m.seq;
  t.utime = m.utime;
  t.arrived = monotonicSeconds();
  t.reading.position = Vector3(m.position[0], m.position[1], m.position[2]);
  t.reading.velocity = Vector3(m.velocity[0], m.velocity[1], m.velocity[2]);
  t.reading.buttons = m.buttons;
  if (oriented) {
    t.reading.has_orientation = true;
    t.reading.orientation =
        Eigen::Quaterniond(m.orientation[0], m.orientation[1], m.orientation[2], m.orientation[3]).normalized();
    t.reading.angular_velocity = Vector3(m.angular_velocity[0], m.angular_velocity[1], m.angular_velocity[2]);
  }
  newest_.write(t);
  ++accepted_;
}

DeviceReading BusDevice::read(double /*t*/) {
  newest_.read(&used_);
  used_age_us_ = wallMicros() - used_.utime;
  const double age = monotonicSeconds() - used_.arrived;
  age_ms_.store(age * 1e3, std::memory_order_relaxed);
  DeviceReading r = used_.reading;
  if (age * 1e3 > kLostMs) {  // the device stopped: hold the tip, let go, ramp the force out
    r.device_lost = true;
    r.buttons = 0;
    r.velocity.setZero();
  }
  return r;
}

void BusDevice::write(const Vector3& force) {
  force_msg_.utime = wallMicros();
  force_msg_.seq = ++cycle_;
  force_msg_.reading_seq = used_.seq;
  force_msg_.reading_utime = used_.utime;
  force_msg_.reading_age_us = used_age_us_;
  for (int k = 0; k < 3; ++k) {
    force_msg_.force[k] = force[k];
    force_msg_.torque[k] = torque_[k];
  }
  const int n = force_msg_.encode(buffer_.data(), 0, static_cast<int>(buffer_.size() - bus::kTrailerBytes));
  if (n > 0) publisher_.publishInPlace(force_channel_, buffer_.data(), static_cast<size_t>(n));
}

int64_t BusDevice::readingsRejected() const {
  int64_t n = 0;
  for (const auto& r : refused_) n += r.load(std::memory_order_relaxed);
  return n + verifier_.counts().refusedTotal();
}

std::string BusDevice::report() const {
  char line[400];
  std::snprintf(line, sizeof line,
                "%s: %lld readings taken; refused %lld undecodable, %lld out of range, %lld out of order; "
                "message check: %s",
                reading_channel_.c_str(), static_cast<long long>(accepted()),
                static_cast<long long>(refused(kUndecodable)), static_cast<long long>(refused(kOutOfRange)),
                static_cast<long long>(refused(kOutOfOrder)), verifier_.summary().c_str());
  return line;
}

IGMS_REGISTER_DEVICE((DeviceEntry{
    "lcm", "lcm[:NAME]      a device in another process: device_reading_t on NAME_READING, device_force_t back on "
           "NAME_FORCE (NAME: IGMS_DEVICE)",
    [](const std::string& args, const DeviceContext& c) -> std::unique_ptr<HapticDevice> {
      return std::make_unique<BusDevice>(args, c);
    }}));

}  // namespace igms
