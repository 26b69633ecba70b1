// A scripted device: timed tip targets and button events from a YAML file,
// deterministic, for tests, the demo and the paper's scenarios.
//
//   frame: scene            # targets in scene coordinates (or: device)
//   hand: {mass: 0.3, k: 400, b: 25}   # optional simulated hand (see below)
//   waypoints:
//     - {t: 0.0, xyz: [0.4, 0.0, 0.5]}
//     - {t: 0.6, link: link3, point: [0.02, 0.22, 0.15], offset: [0, 0, 0.07]}
//                           # a point of a link (link frame) plus a world offset,
//                           # read from the client's estimate when the segment to it starts
//     - {t: 0.9, link: link3, point: [0.02, 0.22, 0.15], offset: [0, 0, 0.04]}   # push 3 cm
//     - {t: 1.5, xyz: [0.4, 0.0, 0.5], rpy: [0, 0, 0.3]}
//                           # a 6-dof device: the tip's orientation (world <- tip, roll pitch yaw, rad),
//                           # slerped between waypoints; waypoints without rpy keep the one before
//   max_torque: 1.0         # N m the device renders (a script with rpy; default 1)
//   max_force: 12           # N the device renders (default 3.3, a PHANToM Omni's peak)
//   buttons:
//     - {t: 2.0, down: true}
//     - {t: 4.0, down: false}
//     - {t: 5.0, down: true, attach: box_b, point: [0, 0, 0.04]}
//                           # this press pulls from a point of the named link or free
//                           # body (its frame), as a click on it in the browser does;
//                           # without attach, the scene's interaction.pull link
//   end: 6.0                # s
//
//   blend: linear           # every segment at constant speed (default: smooth); a waypoint's own
//                           # blend: linear or smooth says how the segment leading to it moves
//
// The tip moves between waypoints with a smooth (C1) blend, or at constant speed. With `hand`, the
// scripted target drives a mass-spring-damper "hand" that also feels the
// rendered force, so force feedback changes the motion as with a person;
// without it the tip follows the script exactly.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "haptic_client/device/haptic_device.h"
#include "haptic_client/device/workspace_map.h"

namespace igms {

class ScriptedDevice : public HapticDevice {
 public:
  // link_pose(name, &X): the client's current estimate of a link's pose in
  // the scene (false when unknown).
  using LinkLookup = std::function<bool(const std::string&, SE3*)>;
  // frame_index(name): the frame's index in the scene's model (-1 when absent); needed by `attach`.
  using FrameLookup = std::function<int(const std::string&)>;

  ScriptedDevice(const std::string& path, const WorkspaceMap& map, LinkLookup link_pose,
                 FrameLookup frame_index = nullptr);
  std::string name() const override { return "scripted:" + path_; }
  DeviceLimits limits() const override { return limits_; }
  DeviceReading read(double t) override;
  void write(const Vector3& force) override { force_ = force; }
  bool finished(double t) const override { return t >= end_; }
  double endTime() const { return end_; }
  // The script as its device saw it (device frame, link waypoints as they were resolved; one not
  // reached yet at the last position), in the example device plugin's targets format
  // (examples/device_plugin/sim_device.c): "hand M K B", "T X Y Z" and "button T DOWN" lines.
  // A press's `attach` and the tip's orientation have no place there and are left out.
  std::string pluginTargets() const;

 private:
  struct Waypoint {
    double t;
    Vector3 xyz;         // scene or device, per frame_scene_
    std::string link;    // when set, the target is the link's point plus xyz (world)
    Vector3 point = Vector3::Zero();  // in the link frame
    Vector3 offset = Vector3::Zero(); // as written (xyz becomes the resolved target)
    bool hold = false;                // the same link, point and offset as the waypoint before: stay there
    bool linear = false;              // the segment to here at constant speed (blend: linear)
    bool resolved = false;
    Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  };
  Vector3 target(double t);
  Eigen::Quaterniond orientationAt(double t) const;
  std::string path_;
  WorkspaceMap map_;
  LinkLookup link_pose_;
  bool frame_scene_ = true;
  std::vector<Waypoint> waypoints_;
  struct ButtonEvent {
    double t = 0.0;
    bool down = false;
    int attach_frame = -1;  // the press pulls from here (-1: the scene's pull link)
    Vector3 attach_point = Vector3::Zero();
  };
  std::vector<ButtonEvent> buttons_;
  double end_ = 0.0;
  DeviceLimits limits_ = simulatedDeviceLimits();
  Vector3 force_ = Vector3::Zero();
  bool has_orientation_ = false;
  Eigen::Quaterniond last_orientation_ = Eigen::Quaterniond::Identity();
  // Simulated hand.
  bool hand_ = false;
  double hand_mass_ = 0.3, hand_k_ = 400.0, hand_b_ = 25.0;
  Vector3 hand_x_ = Vector3::Zero(), hand_v_ = Vector3::Zero();
  double last_t_ = -1.0;
  Vector3 last_position_;         // script frame; starts at the workspace centre
  Vector3 last_device_ = Vector3::Zero();  // device frame, for the velocity
};

}  // namespace igms
