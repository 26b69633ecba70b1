// A device in a shared library of its own (device_plugin.h, the C ABI):
// `--device plugin:PATH.so[:ARGS]` loads it with dlopen, checks the ABI
// version and every symbol, and opens it; any failure is one line naming the
// library and the problem. The servo loop times its read and write as it
// does every device's (device_status_t): a plugin that blocks is counted as
// overrunning, never hidden. A failed call or a non-finite reading is counted
// and the last good reading stands.
#pragma once

#include <atomic>
#include <string>

#include "haptic_client/device/device_plugin.h"
#include "haptic_client/device/haptic_device.h"

namespace igms {

class PluginDevice : public HapticDevice {
 public:
  // spec: "PATH.so" or "PATH.so:ARGS". Throws std::runtime_error with one line naming the library and the problem.
  explicit PluginDevice(const std::string& spec);
  ~PluginDevice() override;
  std::string name() const override { return "plugin:" + path_; }
  DeviceLimits limits() const override { return limits_; }
  DeviceReading read(double t) override;
  void write(const Vector3& force) override;
  void writeTorque(const Vector3& torque) override;
  int64_t failedCalls() const override { return failed_.load(std::memory_order_relaxed); }

 private:
  struct Api {
    int (*abi_version)();
    igms_device* (*open)(const char*, char*, int);
    void (*get_limits)(igms_device*, igms_device_limits*);
    int (*read)(igms_device*, double, igms_device_reading*);
    int (*write)(igms_device*, const double*);
    int (*write_torque)(igms_device*, const double*);
    void (*close)(igms_device*);
  };
  std::string path_;
  void* library_ = nullptr;
  Api api_{};
  igms_device* device_ = nullptr;
  DeviceLimits limits_;
  DeviceReading last_;  // what a failed read repeats
  std::atomic<int64_t> failed_{0};
};

}  // namespace igms
