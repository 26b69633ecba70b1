#include "server/collision/collision_world.h"

#include <fcl/fcl.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/tip_contact.h"
#include "server/collision/fcl_shape.h"

namespace igms {
namespace {

fcl::Transform3d toFcl(const SE3& X) {
  fcl::Transform3d T = fcl::Transform3d::Identity();
  T.linear() = X.R;
  T.translation() = X.p;
  return T;
}

constexpr double kTouching = 1e-9;  // m

// The field's signed distance at p is negative: p is inside the mesh.
bool insideMesh(const CollisionShape& mesh, const SE3& X, const Vector3& p) { return meshSignedDistance(mesh, X, p) < 0.0; }

}  // namespace

struct CollisionWorld::Impl {
  struct Watched {
    int object;  // in the geometry model
    std::unique_ptr<fcl::CollisionObjectd> fcl;
  };
  struct Pair {
    double lower_bound;
    size_t link, obstacle;
  };
  const GeometryModel& geometry;
  std::vector<Watched> links, obstacles;
  std::vector<SE3> link_pose;       // per link, this check's
  std::vector<Vector3> obstacle_centre;  // per obstacle: its bounding sphere's centre, world
  std::vector<Pair> pairs;
  explicit Impl(const GeometryModel& g) : geometry(g) {}
};

CollisionWorld::CollisionWorld(const Model& model, const GeometryModel& geometry,
                               const std::function<bool(const std::string&)>& watched)
    : impl_(std::make_unique<Impl>(geometry)) {
  for (int k = 0; k < geometry.size(); ++k) {
    const GeometryObject& g = geometry.object(k);
    if (!g.has_volume) continue;
    if (g.frame >= 0) {
      // A link fixed to the world (the base) never collides with its surroundings; the free bodies
      // are not watched, the robots' links are.
      if (g.body < 0 || (g.part >= 0 && model.parts[static_cast<size_t>(g.part)].free_body)) continue;
      impl_->links.push_back({k, std::make_unique<fcl::CollisionObjectd>(fclShape(*g.shape))});
    } else if (!g.solid && (!watched || watched(g.name))) {  // a solid obstacle is touched through contact
      auto obj = std::make_unique<fcl::CollisionObjectd>(fclShape(*g.shape), toFcl(g.placement));
      obj->computeAABB();
      impl_->obstacles.push_back({k, std::move(obj)});
      impl_->obstacle_centre.push_back(g.placement.act(g.box_centre));
    }
  }
  impl_->link_pose.resize(impl_->links.size());
  impl_->pairs.reserve(impl_->links.size() * impl_->obstacles.size());
}

CollisionWorld::~CollisionWorld() = default;

bool CollisionWorld::empty() const { return impl_->links.empty() || impl_->obstacles.empty(); }

CollisionReport CollisionWorld::check(const std::vector<SE3>& poses) {
  CollisionReport out;
  fcl::DistanceRequestd request;
  request.enable_signed_distance = false;  // penetration depth (EPA) costs 5-10x; a collision reports <= 0
  // Bounding spheres give a lower bound on each pair's distance: query pairs
  // in that order and stop when no bound can beat the best distance (exact).
  const GeometryModel& geometry = impl_->geometry;
  auto& pairs = impl_->pairs;
  pairs.clear();
  for (size_t l = 0; l < impl_->links.size(); ++l) {
    auto& link = impl_->links[l];
    const GeometryObject& g = geometry.object(link.object);
    const SE3& X = impl_->link_pose[l] = geometry.worldPose(link.object, poses);
    link.fcl->setTransform(toFcl(X));
    const Vector3 centre = X.act(g.box_centre);
    for (size_t o = 0; o < impl_->obstacles.size(); ++o)
      pairs.push_back({(centre - impl_->obstacle_centre[o]).norm() - g.radius -
                           geometry.object(impl_->obstacles[o].object).radius,
                       l, o});
  }
  std::sort(pairs.begin(), pairs.end(), [](const Impl::Pair& a, const Impl::Pair& b) { return a.lower_bound < b.lower_bound; });
  for (const Impl::Pair& p : pairs) {
    if (p.lower_bound >= out.min_distance) break;
    auto& l = impl_->links[p.link];
    const auto& o = impl_->obstacles[p.obstacle];
    const GeometryObject &link = geometry.object(l.object), &obstacle = geometry.object(o.object);
    l.fcl->computeAABB();
    fcl::DistanceResultd result;
    fcl::distance(l.fcl.get(), o.fcl.get(), request, result);
    // FCL says -1 for "colliding", and about 1e-322 for a shape cutting a mesh's triangles.
    if (result.min_distance < kTouching) result.min_distance = 0.0;
    // A mesh's distance is to its triangles: an obstacle whose origin lies inside the mesh (its signed
    // distance field says so) is in collision however far it is from the surface.
    if (result.min_distance > 0.0 && link.shape->kind == CollisionShape::Kind::Mesh && link.shape->field &&
        insideMesh(*link.shape, impl_->link_pose[p.link], obstacle.placement.p))
      result.min_distance = 0.0;
    if (result.min_distance < out.min_distance) {
      out.min_distance = result.min_distance;
      out.closest_link = link.name;
      out.closest_frame = link.frame;
      out.closest_obstacle = obstacle.name;
    }
  }
  out.in_collision = out.min_distance <= 0.0;
  return out;
}

}  // namespace igms
