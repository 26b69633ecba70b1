// Each shape kind's name and the numbers that size it, in one table: the scene
// files read a shape through it, and the programs name one with it. A new kind
// is a row here, then its geometry beside it in core/geometry (bounds, mass
// properties, support point, contact, tip query); docs/architecture.md lists
// what outside the core draws or converts it.
#pragma once

#include <array>
#include <string>

#include "core/model/model.h"

namespace igms {

// One number list of a kind's size, as the scene file spells it: `key` holds `count` numbers
// (a scalar when count is 1), stored from CollisionShape::size[`at`] on, each positive.
struct ShapeDimension {
  const char* key = nullptr;
  int count = 0;
  int at = 0;
};

struct ShapeKindInfo {
  CollisionShape::Kind kind;
  const char* name;                         // the scene's word: "box", "sphere", ...
  std::array<ShapeDimension, 2> dimensions;  // what size holds (key null: unused)
  bool primitive;                           // sized by numbers alone (not a mesh file, not the plane)
};

// The kinds, in the order of CollisionShape::Kind's enumerators.
const std::array<ShapeKindInfo, 6>& shapeKinds();
const ShapeKindInfo& shapeKind(CollisionShape::Kind kind);
// The kind the scene names `name`; null when no kind has that name.
const ShapeKindInfo* shapeKindNamed(const std::string& name);
// "box", "cylinder", "sphere", "mesh", "capsule", "plane".
const char* shapeKindName(CollisionShape::Kind kind);

}  // namespace igms
