// Exact queries on a triangle mesh (its own frame) through its bounding-volume hierarchy
// (core/model/triangle_bvh.h), allocation-free: a fixed stack. They answer at any distance, where
// the mesh's distance field is exact only within its band: the nearest surface point to a large
// sphere's centre, or to a point deep inside. A mesh without a hierarchy is searched triangle by
// triangle.
#pragma once

#include "core/model/closest_point_on_triangle.h"
#include "core/model/triangle_mesh.h"

namespace igms {

struct MeshPoint {
  bool found = false;
  int triangle = -1;
  Vector3 point = Vector3::Zero();  // on the surface
  bool in_face = false;             // inside the triangle's face, not on an edge or a corner
  double distance = 0.0;            // from the query point, unsigned
};

inline TrianglePoint closestOnTriangle(const TriangleMesh& mesh, int t, const Vector3& p) {
  const auto& tri = mesh.triangles[static_cast<size_t>(t)];
  return closestPointOnTriangle(p, mesh.vertices[static_cast<size_t>(tri[0])], mesh.vertices[static_cast<size_t>(tri[1])],
                                mesh.vertices[static_cast<size_t>(tri[2])]);
}

// The unit normal of triangle t (its winding's), zero for a degenerate one.
Vector3 triangleNormal(const TriangleMesh& mesh, int t);

// The squared distance from p to the box [lo, hi] (0 inside).
inline double squaredDistanceToBox(const Vector3& p, const Vector3& lo, const Vector3& hi) {
  return (lo - p).cwiseMax(p - hi).cwiseMax(0.0).squaredNorm();
}

// Walks the hierarchy from p, the nearer child first, skipping a box farther than sqrt(*reach2): the
// bound is read at each box, so visit(triangle) may shrink it (the nearest point's search).
template <typename Visit>
void walkNear(const TriangleMesh& mesh, const Vector3& p, const double* reach2, Visit&& visit) {
  const TriangleBvh& bvh = mesh.bvh;
  if (bvh.empty()) {
    for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t) visit(t);
    return;
  }
  int stack[TriangleBvh::kMaxDepth + 1];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const int at = stack[--top];
    const TriangleBvh::Node& node = bvh.nodes[static_cast<size_t>(at)];
    if (squaredDistanceToBox(p, node.lo, node.hi) > *reach2) continue;
    if (node.count > 0) {
      for (int k = node.first; k < node.first + node.count; ++k) visit(bvh.order[static_cast<size_t>(k)]);
      continue;
    }
    const int a = at + 1, b = node.second;
    const TriangleBvh::Node &na = bvh.nodes[static_cast<size_t>(a)], &nb = bvh.nodes[static_cast<size_t>(b)];
    const bool a_first = squaredDistanceToBox(p, na.lo, na.hi) <= squaredDistanceToBox(p, nb.lo, nb.hi);
    stack[top++] = a_first ? b : a;
    stack[top++] = a_first ? a : b;
  }
}

// Every triangle whose box comes within `radius` of p, in a fixed order: visit(triangle).
template <typename Visit>
void forEachTriangleNear(const TriangleMesh& mesh, const Vector3& p, double radius, Visit&& visit) {
  const double reach2 = radius * radius;
  walkNear(mesh, p, &reach2, visit);
}

// The surface point nearest p within max_distance (found = false: none that near).
MeshPoint nearestOnSurface(const TriangleMesh& mesh, const Vector3& p, double max_distance);

}  // namespace igms
