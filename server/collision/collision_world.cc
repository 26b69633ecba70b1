#include "server/collision/collision_world.h"

#include <fcl/fcl.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/tip_contact.h"

namespace igms {
namespace {

std::shared_ptr<fcl::CollisionGeometryd> geometry(const CollisionShape& s) {
  switch (s.kind) {
    case CollisionShape::Kind::Box: return std::make_shared<fcl::Boxd>(s.size[0], s.size[1], s.size[2]);
    case CollisionShape::Kind::Cylinder: return std::make_shared<fcl::Cylinderd>(s.size[0], s.size[1]);
    case CollisionShape::Kind::Sphere: return std::make_shared<fcl::Sphered>(s.size[0]);
    case CollisionShape::Kind::Capsule: return std::make_shared<fcl::Capsuled>(s.size[0], s.size[1]);
    case CollisionShape::Kind::Plane: return nullptr;  // the ground: the contact layer's, never a ghost
    case CollisionShape::Kind::Mesh: {
      if (!s.triangles) return nullptr;  // a description read as text: no triangles
      auto bvh = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
      std::vector<fcl::Vector3d> vertices(s.triangles->vertices.begin(), s.triangles->vertices.end());
      std::vector<fcl::Triangle> triangles;
      triangles.reserve(s.triangles->triangles.size());
      for (const auto& t : s.triangles->triangles) triangles.emplace_back(t[0], t[1], t[2]);
      bvh->beginModel();
      bvh->addSubModel(vertices, triangles);
      bvh->endModel();
      return bvh;
    }
  }
  return nullptr;
}

fcl::Transform3d toFcl(const SE3& X) {
  fcl::Transform3d T = fcl::Transform3d::Identity();
  T.linear() = X.R;
  T.translation() = X.p;
  return T;
}

// Radius of a sphere about the shape's origin that contains it.
double boundingRadius(const CollisionShape& s) {
  switch (s.kind) {
    case CollisionShape::Kind::Box: return 0.5 * s.size.norm();
    case CollisionShape::Kind::Cylinder: return std::hypot(s.size[0], 0.5 * s.size[1]);
    case CollisionShape::Kind::Sphere: return s.size[0];
    case CollisionShape::Kind::Capsule: return s.size[0] + 0.5 * s.size[1];
    case CollisionShape::Kind::Plane: return 0.0;
    case CollisionShape::Kind::Mesh: {
      double r = 0.0;
      if (s.triangles)
        for (const Vector3& v : s.triangles->vertices) r = std::max(r, v.norm());
      return r;
    }
  }
  return 0.0;
}

constexpr double kTouching = 1e-9;  // m

// The field's signed distance at p is negative: p is inside the mesh.
bool insideMesh(const CollisionShape& mesh, const SE3& X, const Vector3& p) { return meshSignedDistance(mesh, X, p) < 0.0; }

}  // namespace

struct CollisionWorld::Impl {
  struct LinkShape {
    int frame;
    SE3 placement;
    double radius;
    std::unique_ptr<fcl::CollisionObjectd> object;
    const CollisionShape* field = nullptr;  // a mesh with its distance field: for the inside test
  };
  struct ObstacleShape {
    std::string name;
    Vector3 centre;
    double radius;
    std::unique_ptr<fcl::CollisionObjectd> object;
  };
  struct Pair {
    double lower_bound;
    size_t link, obstacle;
  };
  std::vector<Pair> pairs;
  const Model& model;
  std::vector<LinkShape> links;
  std::vector<ObstacleShape> obstacles;
  explicit Impl(const Model& m) : model(m) {}
};

CollisionWorld::CollisionWorld(const Model& model, const std::vector<Obstacle>& obstacles)
    : impl_(std::make_unique<Impl>(model)) {
  for (size_t f = 0; f < model.frames.size(); ++f) {
    if (model.frames[f].body < 0) continue;  // fixed to the world (the base): never collides with its surroundings
    const int part = model.partOfFrame(static_cast<int>(f));
    if (part >= 0 && model.parts[static_cast<size_t>(part)].free_body) continue;  // the robots' links are watched
    for (const auto& s : model.frames[f].collisions)
      if (auto g = geometry(s))
        impl_->links.push_back({static_cast<int>(f), s.placement, boundingRadius(s),
                                std::make_unique<fcl::CollisionObjectd>(g),
                                s.kind == CollisionShape::Kind::Mesh && s.field ? &s : nullptr});
  }
  for (const auto& o : obstacles) {
    if (o.solid) continue;  // a solid obstacle is touched through contact, not watched
    auto g = geometry(o.shape);
    if (!g) continue;
    auto obj = std::make_unique<fcl::CollisionObjectd>(g, toFcl(o.shape.placement));
    obj->computeAABB();
    impl_->obstacles.push_back({o.name, o.shape.placement.p, boundingRadius(o.shape), std::move(obj)});
  }
}

CollisionWorld::~CollisionWorld() = default;

bool CollisionWorld::empty() const { return impl_->links.empty() || impl_->obstacles.empty(); }

CollisionReport CollisionWorld::check(const std::vector<SE3>& poses) {
  CollisionReport out;
  fcl::DistanceRequestd request;
  request.enable_signed_distance = false;  // penetration depth (EPA) costs 5-10x; a collision reports <= 0
  // Bounding spheres give a lower bound on each pair's distance: query pairs
  // in that order and stop when no bound can beat the best distance (exact).
  auto& pairs = impl_->pairs;
  pairs.clear();
  for (size_t l = 0; l < impl_->links.size(); ++l) {
    auto& link = impl_->links[l];
    const SE3 X = poses[static_cast<size_t>(link.frame)] * link.placement;
    link.object->setTransform(toFcl(X));
    for (size_t o = 0; o < impl_->obstacles.size(); ++o) {
      const auto& ob = impl_->obstacles[o];
      pairs.push_back({(X.p - ob.centre).norm() - link.radius - ob.radius, l, o});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Impl::Pair& a, const Impl::Pair& b) { return a.lower_bound < b.lower_bound; });
  for (const Impl::Pair& p : pairs) {
    if (p.lower_bound >= out.min_distance) break;
    auto& l = impl_->links[p.link];
    auto& o = impl_->obstacles[p.obstacle];
    l.object->computeAABB();
    fcl::DistanceResultd result;
    fcl::distance(l.object.get(), o.object.get(), request, result);
    // FCL says -1 for "colliding", and about 1e-322 for a shape cutting a mesh's triangles.
    if (result.min_distance < kTouching) result.min_distance = 0.0;
    // A mesh's distance is to its triangles: an obstacle whose centre lies inside the mesh (its signed
    // distance field says so) is in collision however far it is from the surface.
    if (result.min_distance > 0.0 && l.field && insideMesh(*l.field, poses[static_cast<size_t>(l.frame)] * l.placement, o.centre))
      result.min_distance = 0.0;
    if (result.min_distance < out.min_distance) {
      out.min_distance = result.min_distance;
      out.closest_link = impl_->model.frames[static_cast<size_t>(l.frame)].name;
      out.closest_frame = l.frame;
      out.closest_obstacle = o.name;
    }
  }
  out.in_collision = out.min_distance <= 0.0;
  return out;
}

}  // namespace igms
