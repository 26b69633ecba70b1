// The client's bus thread: receives (states, the server's status) and sends
// the client status at 10 Hz from the servo loop's figures, and the device's
// (device_status_t) and the bus's (bus_status_t) once a second. Also the one
// place the client speaks on the console during the run ("server lost",
// "server back", "device lost"): never the servo loop.
#pragma once

#include <atomic>
#include <string>
#include <thread>

#include "haptic_client/device/haptic_device.h"
#include "haptic_client/servo/client_bus.h"
#include "haptic_client/servo/servo_stats.h"

namespace igms {

struct ClientIdentity {
  int client_id = 1;
  std::string device;
  std::string fallback;
  double lost_ms = 50.0;
};

class ClientStatusThread {
 public:
  ClientStatusThread(ClientBus& bus, ServoStats& stats, const HapticDevice& device, ClientIdentity who);
  ~ClientStatusThread();

 private:
  void run();
  void publishStatus(double now);
  void publishDeviceStatus(int64_t utime);

  ClientBus& bus_;
  ServoStats& stats_;
  const HapticDevice& device_;
  const DeviceLimits limits_;
  const ClientIdentity who_;
  std::atomic<bool> stop_{false};
  int64_t seq_ = 0, last_cycles_ = 0;
  double last_t_;
  std::thread thread_;
};

}  // namespace igms
