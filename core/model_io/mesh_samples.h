// Points spread over a collision mesh's surface, in its frame: what the
// contact layer tests against the shape a mesh touches (shape_contact.h). The
// mesh's vertices, thinned to one per cell of a grid, plus points inside the
// triangles larger than a cell, so that a large flat face is not touched at its
// corners only. At most kMaxMeshSamples: the grid coarsens until they fit.
// Deterministic: the same mesh gives the same points in the same order.
#pragma once

#include <vector>

#include "core/model/triangle_mesh.h"

namespace igms {

constexpr int kMaxMeshSamples = 512;

std::vector<Vector3> meshSurfaceSamples(const TriangleMesh& mesh, double spacing = 0.01);

}  // namespace igms
