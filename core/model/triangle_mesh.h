// A collision mesh as triangles, in the frame the URDF places it in (scale
// applied): what the server's obstacle monitor (FCL) checks and what a
// distance field is built from. Read by core/model_io/mesh_reader.h.
#pragma once

#include <array>
#include <vector>

#include "core/model/spatial.h"
#include "core/model/triangle_bvh.h"

namespace igms {

struct TriangleMesh {
  std::vector<Vector3> vertices;
  std::vector<std::array<int, 3>> triangles;
  TriangleBvh bvh;  // over the triangles (empty until built: the exact queries then test every triangle)
};

}  // namespace igms
