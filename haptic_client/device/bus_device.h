// A device in another process, in any language, over the bus
// (`--device lcm[:NAME]`): it publishes device_reading_t on NAME_READING
// (default IGMS_DEVICE_READING) at its own rate, and the client sends
// device_force_t back on NAME_FORCE once a servo cycle. The readings are
// untrusted: a receive thread of the device's own checks the signature on a
// keyed bus, decodes under a guard, bounds every value and refuses readings
// out of order, counting each refusal by reason; the servo loop takes the
// newest accepted reading without a lock (a seqlock). A reading older than
// lost_ms is a lost device: the loop ramps the force out and lets go, as for
// a lost server, and ramps back when readings return. The force goes out from
// the servo thread, as the client's input does (a sendto of 150 bytes): a
// sender thread woken each cycle cost more here, in the servo loop's write
// time (p99 0.3-0.9 ms: the woken thread preempts it on 2 cores) and in
// latency, than the publish itself.
#pragma once

#include <atomic>
#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "bus/message_verifier.h"
#include "bus/signed_publisher.h"
#include "bus/subscription.h"
#include "core/realtime/latest_value.h"
#include "haptic_client/device/device_registry.h"
#include "haptic_client/device/haptic_device.h"
#include "igms/device_force_t.hpp"
#include "igms/device_reading_t.hpp"

namespace igms {

class BusDevice : public HapticDevice {
 public:
  static constexpr double kLostMs = 50.0;        // no reading for this long: the device is lost
  static constexpr double kFirstReadingS = 10.0; // wait this long for the first reading (its limits)
  static constexpr double kMaxPosition = 1.0;    // m, |p| in the device frame
  static constexpr double kMaxVelocity = 10.0;   // m/s
  static constexpr double kMaxAngularVelocity = 100.0;  // rad/s

  // Refusals by reason, in device_status_t.readings_rejected (their sum) and the exit line.
  enum Refusal { kUndecodable = 0, kOutOfRange, kOutOfOrder, kRefusals };

  // args: "" or a channel base name (letters, digits, '_'). Throws std::runtime_error: a bad name, no
  // LCM, or no valid reading within kFirstReadingS.
  BusDevice(const std::string& args, const DeviceContext& context);
  ~BusDevice() override;
  std::string name() const override { return "lcm:" + base_; }
  DeviceLimits limits() const override { return limits_; }
  DeviceReading read(double t) override;
  void write(const Vector3& force) override;
  void writeTorque(const Vector3& torque) override { torque_ = torque; }
  int64_t readingsRejected() const override;
  std::string report() const override;
  double readingAgeMs() const override { return age_ms_.load(std::memory_order_relaxed); }
  int64_t refused(Refusal why) const { return refused_[why].load(std::memory_order_relaxed); }
  int64_t accepted() const { return accepted_.load(std::memory_order_relaxed); }

 private:
  struct Taken {
    DeviceReading reading;
    int64_t seq = -1, utime = 0;
    double arrived = 0.0;  // monotonic s
  };
  void onReading(const device_reading_t& m);
  void receive();

  std::string base_, reading_channel_, force_channel_;
  DeviceLimits limits_;
  lcm::LCM lcm_;
  bus::MessageVerifier verifier_;  // the receive thread's
  std::unique_ptr<bus::Subscription<device_reading_t>> readings_;  // checked and decoded on the receive thread
  LatestValue<Taken> newest_;
  int64_t newest_seq_ = -1;        // the receive thread's
  std::atomic<int64_t> refused_[kRefusals] = {}, accepted_{0};
  std::atomic<double> age_ms_{0.0};
  std::atomic<bool> stop_{false};
  std::thread thread_;
  // The servo thread's.
  Vector3 torque_ = Vector3::Zero();
  Taken used_;
  int64_t used_age_us_ = 0, cycle_ = 0;
  bus::SignedPublisher publisher_;
  device_force_t force_msg_{};
  std::vector<uint8_t> buffer_;
};

}  // namespace igms
