// A mesh file read as triangles (assimp: STL ASCII and binary, Collada,
// OBJ), every node's transform applied and the URDF's scale too, in the
// frame the URDF places the mesh in.
#pragma once

#include <string>

#include "core/model/triangle_mesh.h"

namespace igms {

// Throws ModelError naming the file and assimp's reason.
TriangleMesh loadTriangleMesh(const std::string& path, const Vector3& scale);

}  // namespace igms
