// The distance between two convex shapes, signed (negative: they overlap by
// that much), with the nearest points and the normal from the first to the
// second. GJK (Gilbert, Johnson, Keerthi 1988) while they are apart, EPA (van
// den Bergen 2001) once their cores overlap. Each shape is a core (a point, a
// segment, a box or a cylinder) rounded by a radius: a sphere is a point, a
// capsule a segment. Fixed-size storage only: no allocation.
//
// igms writes this itself: FCL's GJK/EPA and libccd's EPA allocate per query
// (FCL stays in the server's obstacle monitor and in the tests, where it is the
// independent truth these results are checked against).
#pragma once

#include "core/model/model.h"

namespace igms {

struct ConvexShape {
  enum class Core { Point, Segment, Box, Cylinder };
  Core core = Core::Point;
  Vector3 half = Vector3::Zero();  // segment: (0, 0, half length); box: half extents; cylinder: (radius, 0, half length)
  double radius = 0.0;             // rounds the core (sphere, capsule)
  SE3 pose;                        // world
};

// Box, cylinder, sphere and capsule; false for a mesh or a plane.
bool convexOf(const CollisionShape& shape, const SE3& pose, ConvexShape* out);

// The core's farthest point in world direction d (world).
Vector3 supportPoint(const ConvexShape& s, const Vector3& d);

struct ConvexDistance {
  bool ok = false;                    // false: the iteration failed to produce a direction (degenerate cores)
  double distance = 0.0;              // m, signed, radii included
  Vector3 normal = Vector3::UnitZ();  // world, unit, from a toward b
  Vector3 on_a = Vector3::Zero();     // world: a's surface point nearest b (deepest into b when they overlap)
  Vector3 on_b = Vector3::Zero();     // world: b's, likewise
};

ConvexDistance convexDistance(const ConvexShape& a, const ConvexShape& b);

}  // namespace igms
