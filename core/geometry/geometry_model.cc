#include "core/geometry/geometry_model.h"

#include "core/geometry/shape_bounds.h"
#include "core/kinematics/forward_kinematics.h"

namespace igms {

namespace {

bool isIdentity(const SE3& X) { return X.R == Matrix3::Identity() && X.p == Vector3::Zero(); }

GeometryObject objectOf(const CollisionShape& shape, const std::string& name) {
  GeometryObject g;
  g.shape = &shape;
  g.name = name;
  g.plane = shape.kind == CollisionShape::Kind::Plane;
  boundingBox(shape, g.box_centre, g.box_half);
  g.radius = g.plane ? 0.0 : boundingRadius(shape);
  const bool mesh = shape.kind == CollisionShape::Kind::Mesh;
  g.collides = !mesh || (shape.field && shape.samples);
  g.touchable = !mesh || shape.field;
  g.has_volume = !g.plane && (!mesh || shape.triangles);
  return g;
}

}  // namespace

GeometryModel::GeometryModel(const Model& model, const std::vector<int>& part_material,
                             const std::vector<SceneShape>& scene) {
  for (size_t f = 0; f < model.frames.size(); ++f) {
    const Frame& fr = model.frames[f];
    const int part = model.partOfFrame(static_cast<int>(f));
    for (const CollisionShape& s : fr.collisions) {
      GeometryObject g = objectOf(s, fr.name);
      g.frame = static_cast<int>(f);
      g.body = fr.body;
      g.part = part;
      g.placement = s.placement;
      g.frame_is_body = fr.body >= 0 && isIdentity(fr.placement);
      g.material = part >= 0 && part < static_cast<int>(part_material.size()) ? part_material[static_cast<size_t>(part)] : 0;
      objects_.push_back(g);
    }
  }
  for (const SceneShape& s : scene) {
    own_.push_back(std::make_unique<CollisionShape>(s.shape));
    GeometryObject g = objectOf(*own_.back(), s.name);
    g.placement = s.shape.placement;
    g.material = s.material;
    g.solid = s.solid;
    g.collides = g.collides && s.solid;
    g.touchable = g.touchable && s.solid;
    objects_.push_back(g);
  }
}

void GeometryData::place(const GeometryModel& geometry, const Model& model, const Data& data) {
  for (int k = 0; k < geometry.size(); ++k) {
    const GeometryObject& g = geometry.object(k);
    SE3& X = oMg[static_cast<size_t>(k)];
    if (g.frame < 0) {
      X = g.placement;
    } else if (g.frame_is_body) {
      X = data.oMi[static_cast<size_t>(g.body)] * g.placement;
    } else {
      X = framePose(model, data, g.frame) * g.placement;
    }
  }
}

void GeometryData::place(const GeometryModel& geometry, const std::vector<SE3>& frame_poses) {
  for (int k = 0; k < geometry.size(); ++k) oMg[static_cast<size_t>(k)] = geometry.worldPose(k, frame_poses);
}

}  // namespace igms
