#include "server/collision/collision_world.h"

#include <fcl/fcl.h>

namespace igms {
namespace {

std::shared_ptr<fcl::CollisionGeometryd> geometry(const CollisionShape& s) {
  switch (s.kind) {
    case CollisionShape::Kind::Box: return std::make_shared<fcl::Boxd>(s.size[0], s.size[1], s.size[2]);
    case CollisionShape::Kind::Cylinder: return std::make_shared<fcl::Cylinderd>(s.size[0], s.size[1]);
    case CollisionShape::Kind::Sphere: return std::make_shared<fcl::Sphered>(s.size[0]);
    case CollisionShape::Kind::Mesh: return nullptr;  // meshes are not loaded (no mesh reader here)
  }
  return nullptr;
}

fcl::Transform3d toFcl(const SE3& X) {
  fcl::Transform3d T = fcl::Transform3d::Identity();
  T.linear() = X.R;
  T.translation() = X.p;
  return T;
}

}  // namespace

struct CollisionWorld::Impl {
  struct LinkShape {
    int frame;
    SE3 placement;
    std::unique_ptr<fcl::CollisionObjectd> object;
  };
  struct ObstacleShape {
    std::string name;
    std::unique_ptr<fcl::CollisionObjectd> object;
  };
  const Model& model;
  std::vector<LinkShape> links;
  std::vector<ObstacleShape> obstacles;
  explicit Impl(const Model& m) : model(m) {}
};

CollisionWorld::CollisionWorld(const Model& model, const std::vector<Obstacle>& obstacles)
    : impl_(std::make_unique<Impl>(model)) {
  for (size_t f = 0; f < model.frames.size(); ++f) {
    if (model.frames[f].body < 0) continue;  // fixed to the world (the base): never collides with its surroundings
    for (const auto& s : model.frames[f].collisions)
      if (auto g = geometry(s))
        impl_->links.push_back({static_cast<int>(f), s.placement, std::make_unique<fcl::CollisionObjectd>(g)});
  }
  for (const auto& o : obstacles) {
    auto g = geometry(o.shape);
    if (!g) continue;
    auto obj = std::make_unique<fcl::CollisionObjectd>(g, toFcl(o.shape.placement));
    obj->computeAABB();
    impl_->obstacles.push_back({o.name, std::move(obj)});
  }
}

CollisionWorld::~CollisionWorld() = default;

bool CollisionWorld::empty() const { return impl_->links.empty() || impl_->obstacles.empty(); }

CollisionReport CollisionWorld::check(const std::vector<SE3>& poses) {
  CollisionReport out;
  fcl::DistanceRequestd request;
  request.enable_signed_distance = true;
  for (auto& l : impl_->links) {
    l.object->setTransform(toFcl(poses[static_cast<size_t>(l.frame)] * l.placement));
    l.object->computeAABB();
    for (auto& o : impl_->obstacles) {
      fcl::DistanceResultd result;
      fcl::distance(l.object.get(), o.object.get(), request, result);
      if (result.min_distance < out.min_distance) {
        out.min_distance = result.min_distance;
        out.closest_link = impl_->model.frames[static_cast<size_t>(l.frame)].name;
        out.closest_obstacle = o.name;
      }
    }
  }
  out.in_collision = out.min_distance <= 0.0;
  return out;
}

}  // namespace igms
