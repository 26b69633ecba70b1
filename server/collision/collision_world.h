// Robot links against the scene's ghost obstacles (the geometry world's:
// core/geometry/geometry_model.h), through FCL: collision and minimum
// distance, every step. FCL's queries allocate, so this runs beside
// the step (on the publishing thread), never inside it.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/geometry/geometry_model.h"

namespace igms {

struct CollisionReport {
  bool in_collision = false;
  double min_distance = 1e9;  // m, 0 when in collision (the depth is not computed: EPA costs 5-10x)
  std::string closest_link, closest_obstacle;
  int closest_frame = -1;      // Model frame index of closest_link
};

class CollisionWorld {
 public:
  // Watches the robots' moving links (not the free bodies') against the geometry's ghost obstacles,
  // those `watched` names (all without it).
  CollisionWorld(const Model& model, const GeometryModel& geometry,
                 const std::function<bool(const std::string& obstacle)>& watched = nullptr);
  ~CollisionWorld();
  bool empty() const;
  // link_poses: world pose of every Model frame.
  CollisionReport check(const std::vector<SE3>& link_poses);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace igms
