#include "core/geometry/tip_contact.h"

#include "core/geometry/point_query.h"

namespace igms {

TipContact tipContact(const CollisionShape& shape, const SE3& pose, const Vector3& tip_center, double tip_radius) {
  TipContact out;
  const PointQuery q = pointQuery(shape, pose, tip_center, tip_radius);
  if (!q.valid) return out;
  out.depth = tip_radius - q.distance;
  out.touching = out.depth > 0.0;
  out.normal = q.normal;
  out.point = q.surface;
  return out;
}

double meshSignedDistance(const CollisionShape& mesh, const SE3& pose, const Vector3& p) {
  return fieldSignedDistance(mesh, pose, p);
}

}  // namespace igms
