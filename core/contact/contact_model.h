// ContactModel: what in an environment can touch what, built once from the
// model and the scene's fixed geometry (immutable). Every collision shape
// becomes a geom: on a body (robot links, free bodies) or fixed to the world
// (solid obstacles, the ground, a fixed base's root links), with its material.
// Pairs follow fixed rules: never a body with itself or the world with itself;
// a robot's own links only with contact.self_collision, and never with the links
// next to them (parent and child).
#pragma once

#include <string>
#include <vector>

#include "core/contact/contact_settings.h"
#include "core/model/model.h"

namespace igms {

// Geometry fixed to the world that the model does not hold: a solid obstacle, the ground plane.
struct FixedGeom {
  std::string name;
  CollisionShape shape;  // placement: its world pose
  int material = 0;
};

struct Geom {
  const CollisionShape* shape = nullptr;  // the model frame's, or the contact model's own copy
  int body = -1;        // moving body, -1: fixed to the world
  int part = -1;        // model part (-1: a scene obstacle or the ground)
  int frame = -1;       // model frame (-1: not one of the model's)
  SE3 placement;        // in the body's frame; fixed: world
  int material = 0;
  Vector3 box_centre = Vector3::Zero(), box_half = Vector3::Zero();  // bounding box, shape frame
  bool plane = false;
  std::string name;     // the frame's or the obstacle's
};

class ContactModel {
 public:
  // part_material: per model part, an index into materials; materials[0] is the default.
  ContactModel(const Model& model, const std::vector<int>& part_material, const std::vector<FixedGeom>& fixed,
               const std::vector<Material>& materials, const ContactSettings& settings);
  ContactModel(const ContactModel&) = delete;
  ContactModel& operator=(const ContactModel&) = delete;

  const std::vector<Geom>& geoms() const { return geoms_; }
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
  std::vector<CollisionShape> fixed_shapes_;
  std::vector<Geom> geoms_;
  std::vector<Material> materials_;
  ContactSettings settings_;
  int capacity_ = 0;
  bool any_pair_ = false;
};

}  // namespace igms
