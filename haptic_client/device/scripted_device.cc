#include "haptic_client/device/scripted_device.h"

#include "haptic_client/device/device_registry.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace igms {
namespace {

[[noreturn]] void fail(const std::string& path, const YAML::Node& n, const std::string& what) {
  throw std::runtime_error(path + ":" + std::to_string(n.Mark().line + 1) + ": " + what);
}

Vector3 vec3(const std::string& path, const YAML::Node& n, const char* key) {
  const YAML::Node v = n[key];
  if (!v || !v.IsSequence() || v.size() != 3) fail(path, n, std::string(key) + ": expected 3 numbers");
  return Vector3(v[0].as<double>(), v[1].as<double>(), v[2].as<double>());
}

}  // namespace

ScriptedDevice::ScriptedDevice(const std::string& path, const WorkspaceMap& map, LinkLookup link_pose,
                               FrameLookup frame_index)
    : path_(path), map_(map), link_pose_(std::move(link_pose)) {
  // Until a link-relative first target is known, the tip rests at the workspace centre.
  last_position_ = Vector3::Zero();
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  frame_scene_ = root["frame"] ? root["frame"].as<std::string>() != "device" : true;
  if (frame_scene_) last_position_ = map_.offset;
  if (const YAML::Node h = root["hand"]) {
    hand_ = true;
    hand_mass_ = h["mass"] ? h["mass"].as<double>() : hand_mass_;
    hand_k_ = h["k"] ? h["k"].as<double>() : hand_k_;
    hand_b_ = h["b"] ? h["b"].as<double>() : hand_b_;
    if (!(hand_mass_ > 0 && hand_k_ > 0 && hand_b_ >= 0)) fail(path, h, "hand: mass and k must be positive");
  }
  bool linear = false;  // the script's blend; a waypoint may say its own
  auto blendOf = [&](const YAML::Node& n, bool fallback) {
    if (!n["blend"]) return fallback;
    const std::string b = n["blend"].as<std::string>();
    if (b != "smooth" && b != "linear") fail(path, n["blend"], "blend: expected smooth or linear");
    return b == "linear";
  };
  linear = blendOf(root, false);
  const YAML::Node w = root["waypoints"];
  if (!w || !w.IsSequence() || w.size() == 0) fail(path, root, "waypoints: expected a list");
  for (const auto& p : w) {
    Waypoint wp;
    if (!p["t"]) fail(path, p, "waypoint without t");
    wp.t = p["t"].as<double>();
    wp.linear = blendOf(p, linear);
    if (p["link"]) {
      wp.link = p["link"].as<std::string>();
      wp.xyz = p["offset"] ? vec3(path, p, "offset") : Vector3::Zero();
      wp.point = p["point"] ? vec3(path, p, "point") : Vector3::Zero();
    } else {
      wp.xyz = vec3(path, p, "xyz");
      wp.resolved = true;
    }
    if (!waypoints_.empty() && !(wp.t > waypoints_.back().t)) fail(path, p, "waypoint times must increase");
    if (p["rpy"]) {
      wp.orientation = Eigen::Quaterniond(fromXyzRpy(Vector3::Zero(), vec3(path, p, "rpy")).R);
      has_orientation_ = true;
    } else if (!waypoints_.empty()) {
      wp.orientation = waypoints_.back().orientation;
    }
    if (!wp.link.empty() && !waypoints_.empty()) {
      const Waypoint& before = waypoints_.back();
      wp.hold = before.link == wp.link && before.point == wp.point && before.offset == wp.xyz;
    }
    wp.offset = wp.xyz;
    waypoints_.push_back(wp);
  }
  if (const YAML::Node b = root["buttons"])
    for (const auto& e : b) {
      ButtonEvent event;
      if (!e["t"] || !e["down"]) fail(path, e, "a button event needs t and down");
      event.t = e["t"].as<double>();
      event.down = e["down"].as<bool>();
      if (e["attach"]) {
        const std::string name = e["attach"].as<std::string>();
        if (!event.down) fail(path, e, "attach: only on a press (down: true)");
        if (!frame_index) fail(path, e, "attach: this device has no scene to find '" + name + "' in");
        event.attach_frame = frame_index(name);
        if (event.attach_frame < 0) fail(path, e, "attach: no link or free body '" + name + "' in the scene");
        event.attach_point = e["point"] ? vec3(path, e, "point") : Vector3::Zero();
      }
      buttons_.push_back(event);
    }
  end_ = root["end"] ? root["end"].as<double>() : waypoints_.back().t;
  if (root["max_force"]) {  // the device the script stands for renders this much (default: an Omni's 3.3 N)
    limits_.max_force = root["max_force"].as<double>();
    if (!(limits_.max_force > 0.0 && std::isfinite(limits_.max_force)))
      fail(path, root["max_force"], "max_force: must be positive (N)");
  }
  if (has_orientation_) {
    limits_.max_torque = root["max_torque"] ? root["max_torque"].as<double>() : 1.0;
    if (!(limits_.max_torque > 0.0)) fail(path, root, "max_torque: must be positive (N m)");
  }
}

Vector3 ScriptedDevice::target(double t) {
  // Link-relative waypoints take the link's position when the script reaches
  // the segment leading to them, and keep it (the push then follows the script).
  // One that repeats the waypoint before it (same link, point and offset) is a
  // hold: it keeps that waypoint's position, wherever the link has gone since
  // (a pulled link moves, and re-reading it would move the hand again).
  for (size_t k = 0; k < waypoints_.size(); ++k) {
    Waypoint& w = waypoints_[k];
    const double segment_start = k > 0 ? waypoints_[k - 1].t : w.t;
    if (w.resolved || t < segment_start) continue;
    if (k > 0 && w.hold) {
      if (!waypoints_[k - 1].resolved) continue;
      w.xyz = waypoints_[k - 1].xyz;
      w.resolved = true;
      continue;
    }
    SE3 X;
    if (!link_pose_ || !link_pose_(w.link, &X)) continue;
    const Vector3 p = X.act(w.point);
    w.xyz = (frame_scene_ ? p : map_.toDevice(p)) + w.xyz;
    w.resolved = true;
  }
  auto at = [&](const Waypoint& w) { return w.resolved ? w.xyz : last_position_; };
  if (t <= waypoints_.front().t) return at(waypoints_.front());
  for (size_t k = 1; k < waypoints_.size(); ++k) {
    if (t > waypoints_[k].t) continue;
    const double u = (t - waypoints_[k - 1].t) / (waypoints_[k].t - waypoints_[k - 1].t);
    const double s = waypoints_[k].linear ? u : u * u * (3.0 - 2.0 * u);  // constant speed, or smooth start and stop
    return at(waypoints_[k - 1]) + s * (at(waypoints_[k]) - at(waypoints_[k - 1]));
  }
  return at(waypoints_.back());
}

Eigen::Quaterniond ScriptedDevice::orientationAt(double t) const {
  if (t <= waypoints_.front().t) return waypoints_.front().orientation;
  for (size_t k = 1; k < waypoints_.size(); ++k) {
    if (t > waypoints_[k].t) continue;
    const double u = (t - waypoints_[k - 1].t) / (waypoints_[k].t - waypoints_[k - 1].t);
    const double s = waypoints_[k].linear ? u : u * u * (3.0 - 2.0 * u);  // the positions' blend
    return waypoints_[k - 1].orientation.slerp(s, waypoints_[k].orientation);
  }
  return waypoints_.back().orientation;
}

DeviceReading ScriptedDevice::read(double t) {
  DeviceReading r;
  if (has_orientation_) {  // followed exactly (the simulated hand is translational)
    r.has_orientation = true;
    r.orientation = orientationAt(t);
    if (last_t_ >= 0 && t > last_t_) {
      const Eigen::AngleAxisd turn(r.orientation * last_orientation_.inverse());
      r.angular_velocity = turn.angle() * turn.axis() / (t - last_t_);
    }
    last_orientation_ = r.orientation;
  }
  const Vector3 goal = frame_scene_ ? map_.toDevice(target(t)) : target(t);
  if (!hand_) {
    r.position = goal;
    r.velocity = last_t_ >= 0 && t > last_t_ ? Vector3((goal - last_device_) / (t - last_t_)) : Vector3::Zero();
  } else {
    if (last_t_ < 0) hand_x_ = goal;
    const double dt = last_t_ >= 0 ? std::min(0.01, t - last_t_) : 0.0;
    // The hand: m xdd = k (goal - x) - b xd + F_rendered (semi-implicit Euler; k h^2/m << 1).
    const Vector3 a = (hand_k_ * (goal - hand_x_) - hand_b_ * hand_v_ + force_) / hand_mass_;
    hand_v_ += dt * a;
    hand_x_ += dt * hand_v_;
    r.position = hand_x_;
    r.velocity = hand_v_;
  }
  for (const ButtonEvent& e : buttons_) {
    if (t < e.t) continue;
    r.buttons = e.down ? 1 : 0;
    r.attach_frame = e.down ? e.attach_frame : -1;
    r.attach_point = e.attach_point;
  }
  last_t_ = t;
  last_device_ = r.position;
  last_position_ = frame_scene_ ? map_.toScene(r.position) : r.position;
  return r;
}

std::string ScriptedDevice::pluginTargets() const {
  std::string out = "# " + path_ + " as its device saw it (igms-haptic --export-targets)\n";
  char line[160];
  if (hand_) {
    std::snprintf(line, sizeof line, "hand %.17g %.17g %.17g\n", hand_mass_, hand_k_, hand_b_);
    out += line;
  }
  for (const Waypoint& w : waypoints_) {
    if (w.linear)
      throw std::runtime_error(path_ + ": a linear segment (blend: linear) has no place in the plugin's targets, "
                                       "whose segments are all smooth");
    const Vector3 at = w.resolved ? w.xyz : last_position_;
    const Vector3 d = frame_scene_ ? map_.toDevice(at) : at;
    std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.17g\n", w.t, d.x(), d.y(), d.z());
    out += line;
  }
  for (const ButtonEvent& e : buttons_) {
    std::snprintf(line, sizeof line, "button %.17g %d\n", e.t, e.down ? 1 : 0);
    out += line;
  }
  std::snprintf(line, sizeof line, "end %.17g\n", end_);
  return out + line;
}

}  // namespace igms

namespace igms {
IGMS_REGISTER_DEVICE((DeviceEntry{
    "scripted", "scripted:FILE   timed tip targets and buttons from a YAML script (scenes/push_demo.yaml)",
    [](const std::string& file, const DeviceContext& c) -> std::unique_ptr<HapticDevice> {
      if (file.empty()) throw std::runtime_error("--device scripted:FILE needs the script's file");
      return std::make_unique<ScriptedDevice>(file, c.map, c.link_pose, c.frame_index);
    }}));
}  // namespace igms
