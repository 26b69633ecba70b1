// A point against one collision shape: its signed distance to the surface
// (negative inside), the nearest surface point and the outward normal there.
// Exact for the primitives (box, sphere, cylinder, capsule, plane); a mesh is
// read from its signed distance field and, near the surface, its nearest
// triangles. Allocation-free, constant time. The tip (tip_contact.h) and the
// contact layer's sample points (shape_contact.h) both ask this.
#pragma once

#include <limits>

#include "core/model/model.h"

namespace igms {

struct PointQuery {
  bool valid = false;               // false: a mesh without a field, or p beyond its grid or `reach`
  double distance = 0.0;            // m, signed: negative inside the shape
  Vector3 normal = Vector3::UnitZ();  // world, unit, outward at `surface`
  Vector3 surface = Vector3::Zero();  // world, the nearest point on the surface
};

// shape.placement is ignored; pose is the shape's world pose. Meshes answer only where
// their field can tell (distance below reach); primitives always answer.
PointQuery pointQuery(const CollisionShape& shape, const SE3& pose, const Vector3& p,
                      double reach = std::numeric_limits<double>::infinity());

// A mesh's signed distance at p from its field's grid alone (trilinear, clamped to the field's band;
// +infinity outside the grid or without a field).
double fieldSignedDistance(const CollisionShape& mesh, const SE3& pose, const Vector3& p);

}  // namespace igms
