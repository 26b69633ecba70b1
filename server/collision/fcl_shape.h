// A collision shape in FCL's terms, for the obstacle monitor: FCL's own
// primitive where it has the kind (box, cylinder, sphere, capsule), and
// otherwise the shape's surface from the geometry layer (shape_surface.h) as a
// BVH of triangles, which is also how a mesh goes in. A new shape kind thus
// reaches the monitor without a line here.
#pragma once

#include <fcl/fcl.h>

#include <memory>

#include "core/model/model.h"

namespace igms {

// Null for a plane (the ground is the contact layer's, never a ghost) and for a mesh read without
// its triangles.
std::shared_ptr<fcl::CollisionGeometryd> fclShape(const CollisionShape& shape);
// The shape's surface triangles as FCL's BVH, whatever its kind (null without triangles).
std::shared_ptr<fcl::CollisionGeometryd> fclSurface(const CollisionShape& shape);

}  // namespace igms
