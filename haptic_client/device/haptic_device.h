// A haptic device as the servo loop sees it: read the tip, write a force.
// Real drivers (a PHANToM through OpenHaptics, a Force Dimension device
// through its SDK, CHAI3D) implement this interface in a file of their own,
// behind a CMake option that is off by default; see docs/client.md "Adding a device".
#pragma once

#include <cstdint>
#include <limits>
#include <string>

#include "core/model/spatial.h"

namespace igms {

struct DeviceLimits {
  double max_force = 3.3;          // N (a PHANToM Omni's peak)
  double max_force_step = 1.0;     // N per servo cycle: the most the rendered force may change in one
  // N/m the device renders stably (K < 2b/T); a stiffer coupling is felt scaled down to it.
  // Infinity: a simulated device (scripted, replayed, the browser's mouse), no limit.
  double max_stiffness = 800.0;
  double max_torque = 0.0;         // N m (0: a 3-dof device renders no torque)
  double max_torque_step = 0.02;   // N m per servo cycle
  Vector3 workspace_min = Vector3(-0.08, -0.06, -0.035);  // m, device frame
  Vector3 workspace_max = Vector3(0.08, 0.06, 0.035);
};

// A device that renders to no hand (scripted, replayed, the browser's mouse): igms's defaults,
// with no stiffness limit, so the hand (a simulated one) feels the whole coupling.
inline DeviceLimits simulatedDeviceLimits() {
  DeviceLimits l;
  l.max_stiffness = std::numeric_limits<double>::infinity();
  return l;
}

struct DeviceReading {
  Vector3 position = Vector3::Zero();  // tip, device frame, m
  Vector3 velocity = Vector3::Zero();  // m/s
  bool has_orientation = false;    // a 6-dof device: the 6-D pull
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  // world <- tip (device axes = scene axes)
  Vector3 angular_velocity = Vector3::Zero();  // rad/s
  int buttons = 0;                     // bit 0: the main button
  // Pull from this link point instead of the scene's (-1: the scene's pull
  // link and point). A device that can pick a link (the browser) sets it.
  int attach_frame = -1;
  Vector3 attach_point = Vector3::Zero();  // in the link frame, m
  // A device whose readings stopped coming (a bus device): the loop ramps the force out and lets go,
  // as for a lost server, and back when readings return.
  bool device_lost = false;
};

class HapticDevice {
 public:
  virtual ~HapticDevice() = default;
  virtual std::string name() const = 0;
  virtual DeviceLimits limits() const = 0;
  // The tip at time t (s since the loop started). Must not block or allocate.
  virtual DeviceReading read(double t) = 0;
  // The force to render now, device frame, N (already clamped to limits()).
  virtual void write(const Vector3& force) = 0;
  // The torque to render now, N m (already clamped to limits().max_torque).
  // A 3-dof device ignores it.
  virtual void writeTorque(const Vector3& /*torque*/) {}
  // True when a scripted device has played its whole script.
  virtual bool finished(double /*t*/) const { return false; }
  // Calls the device reported failed, or readings it gave with non-finite values (total).
  // Read by the status thread while the loop runs: an atomic in the device.
  virtual int64_t failedCalls() const { return 0; }
  // A bus device: readings refused as invalid, stale or out of order (total), and the age of the
  // reading behind the last cycle, ms.
  virtual int64_t readingsRejected() const { return 0; }
  virtual double readingAgeMs() const { return 0.0; }
  // One more line for the client's exit summary (a bus device's readings by verdict), or "".
  virtual std::string report() const { return ""; }
};

}  // namespace igms
