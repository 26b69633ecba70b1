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
  const TriangleBvh& bvh = mesh.bvh;
  if (bvh.empty()) {
    for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) offer(t);
  } else {
    // Branch and bound, nearer child first; a box farther than the best so far is skipped.
    int stack[TriangleBvh::kMaxDepth + 1];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const int at = stack[--top];
      const TriangleBvh::Node& node = bvh.nodes[static_cast<size_t>(at)];
      if (squaredDistanceToBox(p, node.lo, node.hi) > best2) continue;
      if (node.count > 0) {
        for (int k = node.first; k < node.first + node.count; ++k) offer(bvh.order[static_cast<size_t>(k)]);
        continue;
      }
      const int a = at + 1, b = node.second;
      const TriangleBvh::Node &na = bvh.nodes[static_cast<size_t>(a)], &nb = bvh.nodes[static_cast<size_t>(b)];
      const bool a_first = squaredDistanceToBox(p, na.lo, na.hi) <= squaredDistanceToBox(p, nb.lo, nb.hi);
      stack[top++] = a_first ? b : a;
      stack[top++] = a_first ? a : b;
    }
  }
  if (best.found) best.distance = std::sqrt(best2);
  return best;
}

}  // namespace igms
