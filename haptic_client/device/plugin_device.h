// A device in a shared library of its own (device_plugin.h, the C ABI):
// `--device plugin:PATH.so[:ARGS]` loads it with dlopen, checks the ABI
// version and every symbol, and opens it; any failure is one line naming the
// library and the problem. Each read and write is timed on the servo loop's
// thread (a fixed histogram, no allocation): the p99, the maximum and the
// calls over 100 us (overruns) are reported, never hidden.
#pragma once

#include <array>
#include <atomic>
#include <string>

#include "haptic_client/device/device_plugin.h"
#include "haptic_client/device/haptic_device.h"

namespace igms {

// Durations of one kind of call, in 1 us bins up to 10 ms (longer ones in the last).
class CallTimes {
 public:
  static constexpr double kOverrunUs = 100.0;
  void add(double us);
  double quantile(double q) const;
  double max() const { return max_; }
  int64_t count() const { return count_; }
  int64_t overruns() const { return overruns_; }

 private:
  std::array<int64_t, 10001> bins_{};
  int64_t count_ = 0, overruns_ = 0;
  double max_ = 0.0;
};

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
  std::string report() const override;
  const CallTimes& readTimes() const { return read_times_; }
  const CallTimes& writeTimes() const { return write_times_; }
  int64_t failedCalls() const { return failed_; }

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
  CallTimes read_times_, write_times_;
  int64_t failed_ = 0;  // reads and writes that returned an error
};

}  // namespace igms
