// The browser as the haptic device (`--device web[:PORT]` or
// `web:ADDR:PORT`): the page serves the live view, and the mouse moves the
// device tip in the scene. The page sends targets at display rate (about
// 60 Hz); read() follows them at 1 kHz through a MouseFollower (smooth,
// with bounded speed and acceleration). The force a PHANToM would render
// goes back to the page (an arrow at the tip and a bar in the HUD). It is a
// 6-dof device: during a pull, Alt-drag turns the grabbed frame (the 6-D
// pull); its torque goes back to the page too.
//
// The page's WebSocket must carry the token printed in the URL (stdout's
// first line); messages from other pages, and malformed ones, are rejected
// and counted (GET /status.json), and the session runs on. The page's
// pause/resume/step/reset/save keys become server commands on the bus.
#pragma once

#include <atomic>
#include <memory>
#include <string>

#include "core/realtime/latest_value.h"
#include "haptic_client/device/device_registry.h"
#include "haptic_client/device/haptic_device.h"
#include "haptic_client/device/mouse_follower.h"

namespace igms {
namespace web {
class ViewService;
class BusFeed;
}  // namespace web

class WebDevice : public HapticDevice {
 public:
  static constexpr int kDefaultPort = 8081;
  using Target = MouseFollower::Target;

  // args: "", "PORT" or "ADDR:PORT". Throws std::runtime_error (bad
  // arguments, port in use). Prints the page's URL with the token on stdout.
  WebDevice(const std::string& args, const DeviceContext& context);
  ~WebDevice() override;
  std::string name() const override { return name_; }
  DeviceLimits limits() const override { return limits_; }
  DeviceReading read(double t) override;
  void write(const Vector3& force) override;
  void writeTorque(const Vector3& torque) override;
  static constexpr double kMaxTurnRate = 4.0;  // rad/s: how fast the device's orientation follows the page's

 private:
  class Page;
  std::string name_;
  DeviceLimits limits_ = simulatedDeviceLimits();
  WorkspaceMap map_;
  LatestValue<Target> target_;
  // Servo-thread state.
  MouseFollower follower_;
  double last_t_ = -1.0;
  Target current_{};
  Vector3 last_force_ = Vector3::Zero();  // rendered last cycle
  Eigen::Quaterniond orientation_ = Eigen::Quaterniond::Identity();
  // Shown on the page.
  LatestValue<Vector3> tip_shown_, force_shown_, torque_shown_;
  std::unique_ptr<Page> page_;
};

}  // namespace igms
