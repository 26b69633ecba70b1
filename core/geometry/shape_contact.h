// Where two collision shapes touch: up to four points, each with its signed
// gap and the normal from the first shape toward the second. A flat contact
// (a box on a plane, a foot's sole on the floor, a can standing on a table)
// gets several points, so that it rests without rocking.
//
//   pairs with a sphere: the sphere's centre against the other shape (exact);
//   capsule-capsule: the segments' nearest points, and each end against the other (exact);
//   box, cylinder, capsule: GJK/EPA's deepest point (convex_distance.h), plus each shape's
//     corners (box), rim points (cylinder) or ends (capsule) against the other, exactly;
//   two overlapping boxes: their 15 separating axes, the least overlap's (exact depth and normal):
//     a face's gives the other box's face clipped to it, an edge pair's the edges' nearest points;
//   a plane: the other shape's lowest points (exact for every primitive: a cylinder's lowest rim
//     point per cap, a box's corners) and a mesh's sample points;
//   a mesh: the other shape's points against the mesh's distance field, and the mesh's sample
//     points against the other shape (exact for a primitive, the field for a mesh). Meshes stay
//     as they are: no convex hull.
// Allocation-free and deterministic: the same inputs give the same points in the same order.
#pragma once

#include "core/model/model.h"

namespace igms {

constexpr int kMaxPairPoints = 4;

struct ContactPoint {
  Vector3 point = Vector3::Zero();    // world: midway between the two surfaces
  Vector3 normal = Vector3::UnitZ();  // world, unit, from a toward b
  double distance = 0.0;              // m, signed: negative where they overlap
};

// The points where a (at pose pa) and b (at pb) are closer than margin, deepest first; \return how
// many (0 to kMaxPairPoints). shape.placement is ignored: the poses are the shapes' world poses.
int shapeContacts(const CollisionShape& a, const SE3& pa, const CollisionShape& b, const SE3& pb, double margin,
                  ContactPoint* out);

}  // namespace igms
