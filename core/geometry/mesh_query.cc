#include "core/geometry/mesh_query.h"

#include <cmath>

namespace igms {

Vector3 triangleNormal(const TriangleMesh& mesh, int t) {
  const auto& tri = mesh.triangles[static_cast<size_t>(t)];
  const Vector3& a = mesh.vertices[static_cast<size_t>(tri[0])];
  const Vector3 n = (mesh.vertices[static_cast<size_t>(tri[1])] - a).cross(mesh.vertices[static_cast<size_t>(tri[2])] - a);
  const double len = n.norm();
  return len > 0.0 ? Vector3(n / len) : Vector3::Zero();
}

MeshPoint nearestOnSurface(const TriangleMesh& mesh, const Vector3& p, double max_distance) {
  MeshPoint best;
  double best2 = max_distance * max_distance;
  auto offer = [&](int t) {
    const TrianglePoint q = closestOnTriangle(mesh, t, p);
    const double d2 = (q.point - p).squaredNorm();
    if (d2 < best2 || (!best.found && d2 <= best2)) {
      best2 = d2;
      best = MeshPoint{true, t, q.point, q.in_face, 0.0};
    }
  };
  walkNear(mesh, p, &best2, offer);  // each better point shrinks the reach
  if (best.found) best.distance = std::sqrt(best2);
  return best;
}

}  // namespace igms
