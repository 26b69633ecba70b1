// Devices by name: `--device NAME[:ARGS]` is looked up in a table that each
// device fills itself (IGMS_REGISTER_DEVICE in its own .cc), so adding a
// device touches its own file and the CMake line that builds it. The device
// sources are an OBJECT library linked straight into the programs, so no
// registration is dropped by the linker.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bus/bus_key.h"
#include "haptic_client/device/haptic_device.h"
#include "haptic_client/device/workspace_map.h"

namespace igms {

// What a device may use when it is made.
struct DeviceContext {
  WorkspaceMap map;  // device -> scene
  // The client's current estimate of a link's world pose (false when unknown).
  std::function<bool(const std::string& link, SE3* pose)> link_pose;
  // A link's index in the model (-1 when there is none of that name).
  std::function<int(const std::string& link)> frame_index;
  std::string lcm_url;  // the bus the client is on (a device may watch it or send commands)
  std::optional<bus::BusKey> key;  // the bus key, for a device that watches or publishes
  bool accept_replay = false;      // a device on the bus takes replayed readings too
};

struct DeviceEntry {
  std::string name;   // before the colon
  std::string usage;  // e.g. "scripted:FILE   timed targets from a YAML script"
  // args: what follows the colon (empty without one). Throws std::runtime_error with a clear message.
  std::function<std::unique_ptr<HapticDevice>(const std::string& args, const DeviceContext& context)> make;
};

class DeviceRegistry {
 public:
  static bool add(DeviceEntry entry);
  // Throws std::runtime_error naming the unknown device and listing the known ones.
  static std::unique_ptr<HapticDevice> make(const std::string& spec, const DeviceContext& context);
  static const std::vector<DeviceEntry>& entries();
  // One line per device, for --help.
  static std::string usage();
};

}  // namespace igms

#define IGMS_REGISTER_DEVICE_CONCAT2(a, b) a##b
#define IGMS_REGISTER_DEVICE_CONCAT(a, b) IGMS_REGISTER_DEVICE_CONCAT2(a, b)
// IGMS_REGISTER_DEVICE(DeviceEntry{...}); at namespace scope in the device's .cc
#define IGMS_REGISTER_DEVICE(entry) \
  static const bool IGMS_REGISTER_DEVICE_CONCAT(igms_device_registered_, __LINE__) = ::igms::DeviceRegistry::add(entry)
