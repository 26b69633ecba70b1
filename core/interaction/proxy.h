// The proxy the tip is held to: a god-object (Zilles & Salisbury 1995), or a
// finger proxy (Ruspini et al. 1997) as CHAI3D's, for a tip sphere. The proxy
// follows the device but cannot enter what it touches:
//  - it moves toward the device in steps of at most half its radius, so it
//    never tunnels through a link or a box, however thin, however deep the
//    device goes;
//  - on a surface it slides along the tangent planes of the shapes it rests
//    on, up to two at once (an edge), and stops in a corner; with Coulomb
//    friction (as CHAI3D's proxy): it sticks while the device is inside the
//    friction cone round the normal, and beyond it slides to the cone's edge;
//  - a shape that moves into it pushes it out along the shape's normal; one
//    that lands over its centre in one cycle (no motion does that in 1 ms: a
//    re-based estimate, a reset) frees it, as below, and so does a device that
//    jumps more than kJump in one update (a script that starts, a remapping).
// The coupling is the spring between the device and the proxy. On a moving
// body it is the paper's push (eq. 3, c = k_p d) with d the device's depth
// behind the surface the proxy rests on; on a fixed one (the ground, a solid
// obstacle, a link fixed to the world) the hand feels a wall.
//
// The proxy is free (it is the device, and touches nothing) while a pull
// holds, and after one (or at start) until the device is clear of every shape
// or at most kEngageDepth into one: a push starts at the surface, so a tip
// that appears deep in a link (a jump, a pull let go inside the wrist, a hand
// that starts on the end-effector to grab it) pushes nothing until it has
// come out.
//
// The server runs one per hand against its exact state, the client one
// against its estimate; both from the same inputs, so a log re-simulates it.
// Built once (allocates); update() does not allocate.
#pragma once

#include <array>
#include <vector>

#include "core/geometry/geometry_model.h"

namespace igms {

// One shape the proxy rests on.
struct ProxyTouch {
  int geom = -1;
  Vector3 normal = Vector3::UnitZ();  // world, out of the shape toward the proxy
  Vector3 surface = Vector3::Zero();  // world, the shape's point under the proxy
};

class Proxy {
 public:
  static constexpr int kMaxTouches = 4;
  static constexpr int kMaxSubsteps = 16;       // of radius / 2 each: 8 cm a cycle for a 1 cm tip
  static constexpr double kJump = 0.05;          // m in one update: not a hand's motion
  static constexpr double kEngageDepth = 0.005;  // m (or the radius, if smaller): a free proxy engages no deeper

  Proxy() = default;
  // The tip touches the geometry's touchable objects (solid, a mesh with its field). friction: the
  // cone's coefficient (0: frictionless).
  explicit Proxy(const GeometryModel& geometry, double friction = 0.0)
      : candidates_(static_cast<size_t>(geometry.size())), friction_(friction) {}

  // One cycle: the proxy toward `device` (radius `radius`) against the geometry as `placed`.
  // free_hold: a pull holds (the proxy is the device).
  void update(const GeometryModel& geometry, const GeometryData& placed, const Vector3& device, double radius,
              bool free_hold);
  // Free from here on until the device comes out (a lost server: a push must start at the surface again).
  void release() {
    free_ = true;
    ntouches_ = 0;
  }

  const Vector3& position() const { return p_; }
  bool free() const { return free_; }
  int touches() const { return ntouches_; }
  const ProxyTouch& touch(int k) const { return touches_[static_cast<size_t>(k)]; }
  // The touch the device is deepest behind (largest (p - device).n, > 0), -1: none; movable_only: among
  // the shapes on moving bodies.
  int deepest(const GeometryModel& geometry, const Vector3& device, bool movable_only) const;
  // Among the shapes near the proxy (its last update's candidates), the nearest on a moving body within
  // `reach` of its surface: where a push would begin within the step. -1: none, or the proxy is free.
  int nearestMovable(const GeometryModel& geometry, const GeometryData& placed, double radius, double reach) const;
  // The spring's stretch the hand feels: p - device while touching, else zero.
  Vector3 stretch(const Vector3& device) const;
  // Cycles the substep budget ran out before the proxy reached its goal (it catches up next cycle).
  int64_t substepLimited() const { return substep_limited_; }

 private:
  void gatherCandidates(const GeometryModel& geometry, const GeometryData& placed, const Vector3& centre, double reach);
  // Pushes p out of every candidate it overlaps (a few passes); collects what it rests on.
  void depenetrate(const GeometryModel& geometry, const GeometryData& placed, double radius);
  bool centreInside(const GeometryModel& geometry, const GeometryData& placed, double radius);
  void collectTouches(const GeometryModel& geometry, const GeometryData& placed, double radius);

  Vector3 p_ = Vector3::Zero();
  bool free_ = true;
  Vector3 last_device_ = Vector3::Zero();
  bool has_device_ = false;
  std::array<ProxyTouch, kMaxTouches> touches_{};
  int ntouches_ = 0;
  std::vector<int> candidates_;
  int ncandidates_ = 0;
  double friction_ = 0.0;
  int64_t substep_limited_ = 0;
};

}  // namespace igms
