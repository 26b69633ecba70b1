// Collision meshes made touchable: each `<collision><mesh>` of a URDF is
// found (package://, file://, relative; resource_path.h), read (assimp) and
// turned into a signed distance field once, at load time. A collision mesh
// that cannot be found or read fails the load, naming the URDF, the link and
// the paths tried: a push that silently touches nothing is worse.
#pragma once

#include <string>

#include "core/model/robot_description.h"

namespace igms {

struct MeshFieldOptions {
  double spacing = 0.002;          // m between grid points (finer for small meshes)
  double band = 0.015;             // m: exact within this distance of the surface
  long max_points = 4'000'000;     // per mesh: a larger mesh gets a coarser grid
  bool use_cache = true;           // distance_field_cache.h
};

void attachDistanceFields(RobotDescription& description, const std::string& urdf_path,
                          const MeshFieldOptions& options = {});

}  // namespace igms
