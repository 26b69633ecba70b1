#include "haptic_client/device/device_registry.h"

#include <algorithm>
#include <stdexcept>

namespace igms {

namespace {
// A function-local table: filled during static initialisation, in whatever order the devices' files run.
std::vector<DeviceEntry>& table() {
  static std::vector<DeviceEntry> t;
  return t;
}
}  // namespace

bool DeviceRegistry::add(DeviceEntry entry) {
  auto& t = table();
  t.push_back(std::move(entry));
  std::sort(t.begin(), t.end(), [](const DeviceEntry& a, const DeviceEntry& b) { return a.name < b.name; });
  return true;
}

const std::vector<DeviceEntry>& DeviceRegistry::entries() { return table(); }

std::string DeviceRegistry::usage() {
  std::string out;
  for (const auto& e : table()) out += "  " + e.usage + "\n";
  return out;
}

std::unique_ptr<HapticDevice> DeviceRegistry::make(const std::string& spec, const DeviceContext& context) {
  const size_t colon = spec.find(':');
  const std::string name = spec.substr(0, colon);
  const std::string args = colon == std::string::npos ? "" : spec.substr(colon + 1);
  for (const auto& e : table())
    if (e.name == name) return e.make(args, context);
  std::string known;
  for (const auto& e : table()) known += (known.empty() ? "" : ", ") + e.name;
  throw std::runtime_error("--device: no device named '" + name + "' (built: " + known +
                           "; real drivers need a vendor SDK, see docs/client.md 'Adding a device')");
}

}  // namespace igms
