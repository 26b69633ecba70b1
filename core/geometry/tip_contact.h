// The haptic tip is a small sphere. Its penetration into a shape, the d and
// the normal of eq. (3), allocation-free: exact for primitives (box, sphere,
// cylinder), from the signed distance field for meshes.
#pragma once

#include "core/model/model.h"

namespace igms {

struct TipContact {
  bool touching = false;
  double depth = 0.0;               // m, > 0 when touching
  Vector3 normal = Vector3::Zero(); // world, unit, out of the shape toward the tip centre
  Vector3 point = Vector3::Zero();  // world, on the shape's surface under the tip
};

// shape.placement is ignored; pose is the shape's world pose. Meshes are
// tested against their distance field and, near the surface, their nearest
// triangles (constant time); a mesh without a field never touches.
TipContact tipContact(const CollisionShape& shape, const SE3& pose, const Vector3& tip_center, double tip_radius);

// A collision mesh's signed distance at p from its field's grid (negative
// inside, clamped to the field's band; +infinity outside the grid or without
// a field): the obstacle monitor's test for a shape wholly inside a mesh.
double meshSignedDistance(const CollisionShape& mesh, const SE3& pose, const Vector3& p);

}  // namespace igms
