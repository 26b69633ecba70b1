#include "core/contact/contact_model.h"

#include <algorithm>
#include <limits>

#include "core/geometry/shape_bounds.h"

namespace igms {

namespace {

// A mesh without samples (a description read as text) cannot touch anything; a primitive always can.
bool touchable(const CollisionShape& s) { return s.kind != CollisionShape::Kind::Mesh || (s.field && s.samples); }

}  // namespace

ContactModel::ContactModel(const Model& model, const std::vector<int>& part_material, const std::vector<FixedGeom>& fixed,
                           const std::vector<Material>& materials, const ContactSettings& settings)
    : model_(model), materials_(materials), settings_(settings) {
  if (materials_.empty()) materials_.push_back(Material{});
  fixed_shapes_.reserve(fixed.size());
  for (const FixedGeom& f : fixed) fixed_shapes_.push_back(f.shape);
  for (size_t fi = 0; fi < model.frames.size(); ++fi) {
    const Frame& f = model.frames[fi];
    const int part = model.partOfFrame(static_cast<int>(fi));
    for (const CollisionShape& s : f.collisions) {
      if (!touchable(s)) continue;
      Geom g;
      g.shape = &s;
      g.body = f.body;
      g.part = part;
      g.frame = static_cast<int>(fi);
      g.placement = f.placement * s.placement;  // body frame (a link fixed to the world: world)
      g.material = part >= 0 && part < static_cast<int>(part_material.size()) ? part_material[static_cast<size_t>(part)] : 0;
      g.plane = s.kind == CollisionShape::Kind::Plane;
      g.name = f.name;
      boundingBox(s, g.box_centre, g.box_half);
      geoms_.push_back(g);
    }
  }
  for (size_t k = 0; k < fixed.size(); ++k) {
    if (!touchable(fixed_shapes_[k])) continue;
    Geom g;
    g.shape = &fixed_shapes_[k];
    g.placement = fixed_shapes_[k].placement;
    g.material = fixed[k].material;
    g.plane = fixed_shapes_[k].kind == CollisionShape::Kind::Plane;
    g.name = fixed[k].name;
    boundingBox(fixed_shapes_[k], g.box_centre, g.box_half);
    geoms_.push_back(g);
  }
  int moving = 0;
  for (const Geom& g : geoms_) moving += g.body >= 0;
  capacity_ = settings_.max_contacts > 0 ? settings_.max_contacts : 8 * moving + 64;
  for (size_t i = 0; i < geoms_.size() && !any_pair_; ++i)
    for (size_t j = i + 1; j < geoms_.size() && !any_pair_; ++j) any_pair_ = canTouch(static_cast<int>(i), static_cast<int>(j));
}

bool ContactModel::canTouch(int i, int j) const {
  const Geom &a = geoms_[static_cast<size_t>(i)], &b = geoms_[static_cast<size_t>(j)];
  if (a.body < 0 && b.body < 0) return false;  // the world does not touch itself
  if (a.body == b.body) return false;
  if (a.part >= 0 && a.part == b.part) {
    // A robot's own links (a free body is one body: caught above).
    if (!settings_.self_collision) return false;
    const auto& parent = model_.parent;
    const int pa = a.body < 0 ? -2 : parent[static_cast<size_t>(a.body)];
    const int pb = b.body < 0 ? -2 : parent[static_cast<size_t>(b.body)];
    if (pa == b.body || pb == a.body) return false;  // parent and child (a root and the world-fixed links)
  }
  return true;
}

}  // namespace igms
