// A shape's surface as triangles, for the engines that are not igms's own and
// take a triangle mesh where they lack a kind: FCL's BVH (the obstacle monitor),
// ODE's trimesh (the cross-check) and the page's drawing. Every vertex lies on
// the exact surface (the polyhedron is inscribed: its volume falls short by the
// tessellation's sagitta, 1 - cos(pi / segments) of the radius), the winding is
// outward, and the surface is closed. A mesh is its own triangles; a plane, or a
// mesh read without its triangles, has none.
#pragma once

#include "core/model/model.h"
#include "core/model/triangle_mesh.h"

namespace igms {

// `segments`: vertices around a round shape's axis (rings along it: half as many). Shape frame, no BVH.
TriangleMesh shapeSurface(const CollisionShape& shape, int segments = 24);

}  // namespace igms
