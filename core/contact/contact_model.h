// ContactModel: what in the geometry world can touch what, and with which
// material (immutable). Its geoms are the geometry model's objects
// (core/geometry/geometry_model.h), by the same index; those that cannot
// collide (a ghost obstacle, a mesh without its field and samples) touch
// nothing. Pairs follow fixed rules: never a body with itself or the world
// with itself; a robot's own links only with contact.self_collision, and never
// with the links next to them (parent and child).
#pragma once

#include <vector>

#include "core/contact/contact_settings.h"
#include "core/geometry/geometry_model.h"

namespace igms {

class ContactModel {
 public:
  // materials[0] is the default; each object's material indexes them.
  ContactModel(const Model& model, const GeometryModel& geometry, const std::vector<Material>& materials,
               const ContactSettings& settings);
  ContactModel(const ContactModel&) = delete;
  ContactModel& operator=(const ContactModel&) = delete;

  const GeometryModel& geometry() const { return geometry_; }
  // The geoms: the geometry model's objects.
  int size() const { return geometry_.size(); }
  const GeometryObject& geom(int k) const { return geometry_.object(k); }
  const ContactSettings& settings() const { return settings_; }
  const Material& material(int k) const { return materials_[static_cast<size_t>(k)]; }
  // May geoms i and j touch (the rules above)?
  bool canTouch(int i, int j) const;
  // Contact points the buffers hold (settings.max_contacts, or from the scene's size).
  int capacity() const { return capacity_; }
  // Any pair at all: false for one robot alone in empty space (the step then skips contact).
  bool empty() const { return !any_pair_; }

 private:
  const Model& model_;
  const GeometryModel& geometry_;
  std::vector<Material> materials_;
  ContactSettings settings_;
  int capacity_ = 0;
  bool any_pair_ = false;
};

}  // namespace igms
