#include "haptic_client/device/replay_device.h"

#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <stdexcept>

#include "haptic_client/device/device_registry.h"

#include "igms/haptic_input_t.hpp"
#include "safe_decode.h"

namespace igms {

ReplayDevice::ReplayDevice(const std::string& path, const WorkspaceMap& map, const std::string& channel)
    : path_(path), map_(map) {
  lcm::LogFile log(path, "r");
  if (!log.good()) throw std::runtime_error(path + ": cannot open the LCM log");
  int64_t first = -1, last_seq = -1;
  int32_t client = -1;
  while (const lcm::LogEvent* e = log.readNextEvent()) {
    if (e->channel != channel) continue;
    haptic_input_t m;
    if (!igms::safeDecode(e->data, static_cast<int>(e->datalen), &m)) continue;
    if (client < 0) client = m.client_id;
    if (m.client_id != client) continue;  // one hand: the log's first client's
    if (m.seq <= last_seq) continue;      // replays of one input
    last_seq = m.seq;
    if (first < 0) first = m.utime;
    int buttons = m.buttons;
    if (m.mode == haptic_input_t::MODE_PULL) buttons |= 1;  // a pull is the main button held
    Sample sample{1e-6 * static_cast<double>(m.utime - first),
                  Vector3(m.tip_position[0], m.tip_position[1], m.tip_position[2]), buttons};
    if (m.has_orientation) {
      sample.has_orientation = true;
      sample.orientation = Eigen::Quaterniond(m.tip_orientation[0], m.tip_orientation[1], m.tip_orientation[2],
                                              m.tip_orientation[3]).normalized();
      sample.angular_velocity = Vector3(m.tip_angular_velocity[0], m.tip_angular_velocity[1], m.tip_angular_velocity[2]);
      limits_.max_torque = 1.0;  // a 6-dof session
    }
    samples_.push_back(sample);
  }
  if (samples_.empty()) throw std::runtime_error(path + ": no " + channel + " events to replay");
}

DeviceReading ReplayDevice::read(double t) {
  DeviceReading r;
  while (cursor_ + 1 < samples_.size() && samples_[cursor_ + 1].t <= t) ++cursor_;
  while (cursor_ > 0 && samples_[cursor_].t > t) --cursor_;
  const Sample& a = samples_[cursor_];
  if (cursor_ + 1 < samples_.size() && t > a.t) {
    const Sample& b = samples_[cursor_ + 1];
    const double u = (t - a.t) / (b.t - a.t);
    r.position = map_.toDevice(a.tip + u * (b.tip - a.tip));
    r.velocity = (b.tip - a.tip) / (map_.scale * (b.t - a.t));
    r.orientation = a.orientation.slerp(u, b.orientation);
  } else {
    r.position = map_.toDevice(a.tip);
    r.orientation = a.orientation;
  }
  r.has_orientation = a.has_orientation;
  r.angular_velocity = a.angular_velocity;
  r.buttons = a.buttons;
  return r;
}

}  // namespace igms

namespace igms {
IGMS_REGISTER_DEVICE((DeviceEntry{
    "replay", "replay:LOG      the tip motion and buttons of a recorded session (an LCM log)",
    [](const std::string& log, const DeviceContext& c) -> std::unique_ptr<HapticDevice> {
      if (log.empty()) throw std::runtime_error("--device replay:LOG needs the log's file");
      return std::make_unique<ReplayDevice>(log, c.map);
    }}));
}  // namespace igms
