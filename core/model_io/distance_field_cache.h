// Distance fields kept on disk between runs, keyed by a hash of the mesh's
// triangles and the grid's settings: a robot with many meshes (Talos: 52)
// builds them once, then loads in a fraction of the time. The folder is
// $IGMS_CACHE_DIR, else $XDG_CACHE_HOME/igms, else ~/.cache/igms; when it
// cannot be written, nothing is cached and nothing fails. A damaged or
// foreign file is ignored and rebuilt.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/model/distance_field.h"
#include "core/model/triangle_mesh.h"

namespace igms {

// FNV-1a 64 over the vertices, the triangles and the settings.
uint64_t distanceFieldKey(const TriangleMesh& mesh, double spacing, double band);

std::optional<DistanceField> readCachedField(uint64_t key);
void writeCachedField(uint64_t key, const DistanceField& field);

}  // namespace igms
