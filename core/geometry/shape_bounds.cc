#include "core/geometry/shape_bounds.h"

#include <cmath>
#include <limits>

namespace igms {

void boundingBox(const CollisionShape& s, Vector3& centre, Vector3& half) {
  centre.setZero();
  switch (s.kind) {
    case CollisionShape::Kind::Box: half = 0.5 * s.size; return;
    case CollisionShape::Kind::Sphere: half.setConstant(s.size[0]); return;
    case CollisionShape::Kind::Cylinder: half = Vector3(s.size[0], s.size[0], 0.5 * s.size[1]); return;
    case CollisionShape::Kind::Capsule: half = Vector3(s.size[0], s.size[0], 0.5 * s.size[1] + s.size[0]); return;
    case CollisionShape::Kind::Mesh: {
      Vector3 lo = Vector3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
      if (s.samples)
        for (const Vector3& p : *s.samples) {
          lo = lo.cwiseMin(p);
          hi = hi.cwiseMax(p);
        }
      if (s.triangles)
        for (const Vector3& p : s.triangles->vertices) {
          lo = lo.cwiseMin(p);
          hi = hi.cwiseMax(p);
        }
      if (!(lo.array() <= hi.array()).all()) lo = hi = Vector3::Zero();
      centre = 0.5 * (lo + hi);
      half = 0.5 * (hi - lo);
      return;
    }
    case CollisionShape::Kind::Plane: half.setZero(); return;
  }
}

double boundingRadius(const CollisionShape& s) {
  switch (s.kind) {
    case CollisionShape::Kind::Sphere: return s.size[0];
    case CollisionShape::Kind::Capsule: return s.size[0] + 0.5 * s.size[1];
    case CollisionShape::Kind::Cylinder: return std::hypot(s.size[0], 0.5 * s.size[1]);
    default: {
      Vector3 centre, half;
      boundingBox(s, centre, half);
      return half.norm();
    }
  }
}

}  // namespace igms
