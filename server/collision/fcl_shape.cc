#include "server/collision/fcl_shape.h"

#include <vector>

#include "core/geometry/shape_surface.h"

namespace igms {

std::shared_ptr<fcl::CollisionGeometryd> fclSurface(const CollisionShape& s) {
  const TriangleMesh surface = shapeSurface(s);
  if (surface.triangles.empty()) return nullptr;
  auto bvh = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  const std::vector<fcl::Vector3d> vertices(surface.vertices.begin(), surface.vertices.end());
  std::vector<fcl::Triangle> triangles;
  triangles.reserve(surface.triangles.size());
  for (const auto& t : surface.triangles) triangles.emplace_back(t[0], t[1], t[2]);
  bvh->beginModel();
  bvh->addSubModel(vertices, triangles);
  bvh->endModel();
  return bvh;
}

std::shared_ptr<fcl::CollisionGeometryd> fclShape(const CollisionShape& s) {
  switch (s.kind) {
    case CollisionShape::Kind::Box: return std::make_shared<fcl::Boxd>(s.size[0], s.size[1], s.size[2]);
    case CollisionShape::Kind::Cylinder: return std::make_shared<fcl::Cylinderd>(s.size[0], s.size[1]);
    case CollisionShape::Kind::Sphere: return std::make_shared<fcl::Sphered>(s.size[0]);
    case CollisionShape::Kind::Capsule: return std::make_shared<fcl::Capsuled>(s.size[0], s.size[1]);
    case CollisionShape::Kind::Plane: return nullptr;
    default: return fclSurface(s);  // a mesh, and any kind FCL has no primitive for
  }
}

}  // namespace igms
