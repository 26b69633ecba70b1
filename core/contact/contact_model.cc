#include "core/contact/contact_model.h"

namespace igms {

ContactModel::ContactModel(const Model& model, const GeometryModel& geometry, const std::vector<Material>& materials,
                           const ContactSettings& settings)
    : model_(model), geometry_(geometry), materials_(materials), settings_(settings) {
  if (materials_.empty()) materials_.push_back(Material{});
  int moving = 0;
  for (const GeometryObject& g : geometry_.objects()) moving += g.collides && g.body >= 0;
  capacity_ = settings_.max_contacts > 0 ? settings_.max_contacts : 8 * moving + 64;
  for (int i = 0; i < size() && !any_pair_; ++i)
    for (int j = i + 1; j < size() && !any_pair_; ++j) any_pair_ = canTouch(i, j);
}

bool ContactModel::canTouch(int i, int j) const {
  const GeometryObject &a = geom(i), &b = geom(j);
  if (!a.collides || !b.collides) return false;
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
