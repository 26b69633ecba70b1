// The mass properties of a solid shape of uniform density: its volume, centre
// of mass and inertia about the centre of mass (shape axes). Closed forms for
// the primitives; a closed triangle mesh by the divergence theorem (signed
// tetrahedra from the origin; Eberly, "Polyhedral Mass Properties").
#pragma once

#include "core/model/model.h"

namespace igms {

struct MassProperties {
  double volume = 0.0;             // m^3
  Vector3 com = Vector3::Zero();   // shape frame
  Matrix3 inertia = Matrix3::Zero();  // about the com, per unit density (kg m^2 per kg/m^3)
};

// For a mesh, `mesh` holds its triangles (outward winding); primitives ignore it. Throws
// std::invalid_argument for a plane or a mesh that encloses no volume.
MassProperties shapeMassProperties(const CollisionShape& shape, const TriangleMesh* mesh = nullptr);

}  // namespace igms
