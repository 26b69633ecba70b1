// The geometry world: every shape in a scene, built once (GeometryModel,
// immutable) and placed once per step (GeometryData), as Pinocchio's
// GeometryModel and GeometryData sit beside Model and Data. The contact layer,
// the hand's proxy and the obstacle monitor index into the same objects:
//  - a model frame's collision shapes, in frame order (robot links, free bodies;
//    a fixed base's root links are fixed to the world);
//  - the scene's own shapes, in the scene's order: solid obstacles, ghost
//    obstacles (watched by the monitor, touched by nothing) and the ground.
// An object's world pose is its frame's world pose times its placement (the
// scene's own: their placement is the world pose), whoever places it.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/model/data.h"
#include "core/model/model.h"

namespace igms {

// A shape the scene holds itself (the model does not): an obstacle or the ground.
struct SceneShape {
  std::string name;
  CollisionShape shape;  // placement: its world pose
  int material = 0;
  bool solid = true;     // false: a ghost, watched only
};

struct GeometryObject {
  const CollisionShape* shape = nullptr;  // the model frame's, or the geometry model's own copy
  std::string name;      // the frame's or the scene's
  int frame = -1;        // the model frame that carries it; -1: the scene's own
  int body = -1;         // the moving body it is on; -1: fixed to the world
  int part = -1;         // its model part; -1: the scene's own
  SE3 placement;         // in the frame; the scene's own: the world pose
  bool frame_is_body = false;  // the frame is its body's own (placement exactly the identity)
  int material = 0;      // index into the scene's materials (0: default)
  bool solid = true;     // false: a ghost obstacle
  bool plane = false;
  Vector3 box_centre = Vector3::Zero(), box_half = Vector3::Zero();  // bounding box, shape frame
  double radius = 0.0;   // a sphere about box_centre that holds the shape (shape_bounds.h); a plane: 0

  // What can use it (set once built). Contact: a solid primitive, or a mesh with its distance field and
  // surface samples (a description read as text has neither). The tip: a solid primitive, or a mesh
  // with its field. The obstacle monitor's exact distance (FCL): anything but a plane; a mesh with its
  // triangles.
  bool collides = false, touchable = false, has_volume = false;
};

class GeometryModel {
 public:
  // part_material: per model part, its material (missing parts: 0).
  GeometryModel(const Model& model, const std::vector<int>& part_material, const std::vector<SceneShape>& scene);
  GeometryModel(const GeometryModel&) = delete;
  GeometryModel& operator=(const GeometryModel&) = delete;

  int size() const { return static_cast<int>(objects_.size()); }
  const GeometryObject& object(int k) const { return objects_[static_cast<size_t>(k)]; }
  const std::vector<GeometryObject>& objects() const { return objects_; }
  // Object k's world pose, given every model frame's world pose (Data::oMf, or a client's estimate).
  SE3 worldPose(int k, const std::vector<SE3>& frame_poses) const {
    const GeometryObject& g = object(k);
    return g.frame < 0 ? g.placement : frame_poses[static_cast<size_t>(g.frame)] * g.placement;
  }

 private:
  std::vector<std::unique_ptr<CollisionShape>> own_;  // the scene's shapes (stable addresses)
  std::vector<GeometryObject> objects_;
};

// Every object's world pose at one state. Allocation-free after construction.
struct GeometryData {
  explicit GeometryData(const GeometryModel& geometry) : oMg(static_cast<size_t>(geometry.size())) {}
  std::vector<SE3> oMg;

  // At the body poses in data.oMi (bodyKinematics): each frame's pose as framePose forms it, times
  // the object's placement (a frame that is its body's own skips the identity: the same bits).
  void place(const GeometryModel& geometry, const Model& model, const Data& data);
  // At every frame's world pose (a client's estimate).
  void place(const GeometryModel& geometry, const std::vector<SE3>& frame_poses);
};

}  // namespace igms
