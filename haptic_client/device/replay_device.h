// A replay device: the tip motion and buttons of a recorded session, read from
// a standard LCM event log (the haptic inputs on IGMS_HAPTIC_INPUT), so the
// same hand motion can be played against a changed scene. Positions were
// recorded in scene coordinates and are mapped back to the device. A log of
// several hands replays its first client's; a 6-dof session's orientation
// is replayed too.
#pragma once

#include <string>
#include <vector>

#include "haptic_client/device/scripted_device.h"

namespace igms {

class ReplayDevice : public HapticDevice {
 public:
  // Throws std::runtime_error naming the log when it cannot be read or holds no input.
  ReplayDevice(const std::string& log_path, const WorkspaceMap& map, const std::string& channel = "IGMS_HAPTIC_INPUT");
  std::string name() const override { return "replay:" + path_; }
  DeviceLimits limits() const override { return limits_; }
  DeviceReading read(double t) override;
  void write(const Vector3&) override {}
  bool finished(double t) const override { return samples_.empty() || t > samples_.back().t; }
  size_t samples() const { return samples_.size(); }

 private:
  struct Sample {
    double t;            // s since the first recorded input
    Vector3 tip;         // scene
    int buttons;
    bool has_orientation = false;  // a 6-dof device's session
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
    Vector3 angular_velocity = Vector3::Zero();
  };
  std::string path_;
  WorkspaceMap map_;
  std::vector<Sample> samples_;
  size_t cursor_ = 0;
  DeviceLimits limits_ = simulatedDeviceLimits();
};

}  // namespace igms
