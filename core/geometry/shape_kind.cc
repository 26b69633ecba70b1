#include "core/geometry/shape_kind.h"

namespace igms {

namespace {

using Kind = CollisionShape::Kind;

// size: a box's extents; a cylinder's and a capsule's radius, then the axis between the caps' centres;
// a sphere's radius (core/model/model.h).
const std::array<ShapeKindInfo, 6> kKinds = {{
    {Kind::Box, "box", {{{"size", 3, 0}, {}}}, true},
    {Kind::Cylinder, "cylinder", {{{"radius", 1, 0}, {"length", 1, 1}}}, true},
    {Kind::Sphere, "sphere", {{{"radius", 1, 0}, {}}}, true},
    {Kind::Mesh, "mesh", {{{}, {}}}, false},
    {Kind::Capsule, "capsule", {{{"radius", 1, 0}, {"length", 1, 1}}}, true},
    {Kind::Plane, "plane", {{{}, {}}}, false},
}};

}  // namespace

const std::array<ShapeKindInfo, 6>& shapeKinds() { return kKinds; }

const ShapeKindInfo& shapeKind(Kind kind) { return kKinds[static_cast<size_t>(kind)]; }

const ShapeKindInfo* shapeKindNamed(const std::string& name) {
  for (const ShapeKindInfo& k : kKinds)
    if (name == k.name) return &k;
  return nullptr;
}

const char* shapeKindName(Kind kind) { return shapeKind(kind).name; }

}  // namespace igms
