// Builds the signed distance field of a closed triangle mesh: exact
// point-to-triangle distances at the grid points within `band` of the
// surface; the sign from the nearest triangles' normals (their sum where
// several are equally near: an edge or a vertex), and beyond the band from
// a flood fill from the grid's boundary, which is outside. The grid covers
// the mesh's bounding box grown by `band`.
#pragma once

#include "core/model/distance_field.h"
#include "core/model/triangle_mesh.h"

namespace igms {

DistanceField buildDistanceField(const TriangleMesh& mesh, double spacing, double band);

// The exact signed distance from p to the mesh, by brute force over every
// triangle (for tests and the field's own checks): the sign as above.
double exactSignedDistance(const TriangleMesh& mesh, const Vector3& p);

}  // namespace igms
