#include "haptic_client/device/plugin_device.h"

#include <dlfcn.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "haptic_client/device/device_registry.h"

namespace igms {
namespace {

bool finite3(const double* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

}  // namespace

PluginDevice::PluginDevice(const std::string& spec) {
  const size_t colon = spec.find(':');
  path_ = spec.substr(0, colon);
  const std::string args = colon == std::string::npos ? "" : spec.substr(colon + 1);
  auto fail = [&](const std::string& why) { return std::runtime_error("--device plugin:" + path_ + ": " + why); };
  if (path_.empty()) throw std::runtime_error("--device plugin:PATH.so[:ARGS] needs the library's path");
  // A name without a '/' is looked up along dlopen's search path (LD_LIBRARY_PATH, the cache): whatever
  // library of that name comes first would run in the servo loop. Only a path is loaded.
  if (path_.find('/') == std::string::npos)
    throw fail("a path to the library is needed (./" + path_ + ", or an absolute one), not a name to search for");
  library_ = dlopen(path_.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!library_) throw fail(std::string("cannot load it: ") + dlerror());
  auto symbol = [&](const char* name) {
    void* s = dlsym(library_, name);
    if (!s) {
      dlclose(library_);
      library_ = nullptr;
      throw fail(std::string("no symbol ") + name + " (see <igms/device_plugin.h>: every function is required)");
    }
    return s;
  };
  api_.abi_version = reinterpret_cast<int (*)()>(symbol("igms_device_abi_version"));
  api_.open = reinterpret_cast<igms_device* (*)(const char*, char*, int)>(symbol("igms_device_open"));
  api_.get_limits = reinterpret_cast<void (*)(igms_device*, igms_device_limits*)>(symbol("igms_device_get_limits"));
  api_.read = reinterpret_cast<int (*)(igms_device*, double, igms_device_reading*)>(symbol("igms_device_read"));
  api_.write = reinterpret_cast<int (*)(igms_device*, const double*)>(symbol("igms_device_write"));
  api_.write_torque = reinterpret_cast<int (*)(igms_device*, const double*)>(symbol("igms_device_write_torque"));
  api_.close = reinterpret_cast<void (*)(igms_device*)>(symbol("igms_device_close"));
  if (const int v = api_.abi_version(); v != IGMS_DEVICE_PLUGIN_ABI) {
    dlclose(library_);
    library_ = nullptr;
    throw fail("built for device plugin ABI " + std::to_string(v) + ", this igms-haptic speaks " +
               std::to_string(IGMS_DEVICE_PLUGIN_ABI) + " (rebuild it against this <igms/device_plugin.h>)");
  }
  char error[256] = "";
  device_ = api_.open(args.c_str(), error, sizeof error);
  if (!device_) {
    error[sizeof error - 1] = '\0';
    dlclose(library_);
    library_ = nullptr;
    throw fail(std::string("open failed: ") + (error[0] ? error : "(the plugin gave no reason)"));
  }
  igms_device_limits l{};
  api_.get_limits(device_, &l);
  // A limit the plugin leaves at 0 or gives as nonsense keeps igms's default (a PHANToM Omni's).
  auto take = [](double v, double* out) {
    if (std::isfinite(v) && v > 0) *out = v;
  };
  take(l.max_force, &limits_.max_force);
  take(l.max_force_step, &limits_.max_force_step);
  if (std::isinf(l.max_stiffness) && l.max_stiffness > 0) limits_.max_stiffness = l.max_stiffness;  // a simulated device
  else take(l.max_stiffness, &limits_.max_stiffness);
  if (std::isfinite(l.max_torque) && l.max_torque >= 0) limits_.max_torque = l.max_torque;
  take(l.max_torque_step, &limits_.max_torque_step);
  if (finite3(l.workspace_min) && finite3(l.workspace_max) && l.workspace_max[0] > l.workspace_min[0] &&
      l.workspace_max[1] > l.workspace_min[1] && l.workspace_max[2] > l.workspace_min[2]) {
    limits_.workspace_min = Vector3(l.workspace_min[0], l.workspace_min[1], l.workspace_min[2]);
    limits_.workspace_max = Vector3(l.workspace_max[0], l.workspace_max[1], l.workspace_max[2]);
  }
}

PluginDevice::~PluginDevice() {
  if (device_) api_.close(device_);
  if (library_) dlclose(library_);
}

DeviceReading PluginDevice::read(double t) {
  igms_device_reading r{};
  const int rc = api_.read(device_, t, &r);
  // A failed read, or one with a non-finite value, is counted and the last good reading stands.
  if (rc != 0 || !finite3(r.position) || !finite3(r.velocity) || (r.has_orientation && !finite3(r.angular_velocity))) {
    ++failed_;
    return last_;
  }
  DeviceReading out;
  out.position = Vector3(r.position[0], r.position[1], r.position[2]);
  out.velocity = Vector3(r.velocity[0], r.velocity[1], r.velocity[2]);
  out.buttons = r.buttons;
  if (r.has_orientation) {
    Eigen::Quaterniond q(r.orientation[0], r.orientation[1], r.orientation[2], r.orientation[3]);
    if (std::isfinite(q.norm()) && q.norm() > 0.5) {
      out.has_orientation = true;
      out.orientation = q.normalized();
      out.angular_velocity = Vector3(r.angular_velocity[0], r.angular_velocity[1], r.angular_velocity[2]);
    }
  }
  last_ = out;
  return out;
}

void PluginDevice::write(const Vector3& force) {
  const double f[3] = {force.x(), force.y(), force.z()};
  if (api_.write(device_, f) != 0) ++failed_;
}

void PluginDevice::writeTorque(const Vector3& torque) {
  const double m[3] = {torque.x(), torque.y(), torque.z()};
  if (api_.write_torque(device_, m) != 0) ++failed_;
}

IGMS_REGISTER_DEVICE((DeviceEntry{
    "plugin", "plugin:PATH.so[:ARGS]  a device in a shared library of its own (<igms/device_plugin.h>)",
    [](const std::string& spec, const DeviceContext&) -> std::unique_ptr<HapticDevice> {
      return std::make_unique<PluginDevice>(spec);
    }}));

}  // namespace igms
