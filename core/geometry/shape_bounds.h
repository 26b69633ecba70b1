// A collision shape's bounding box in its own frame: the broad phase of the
// contact detection and the proxy's cheap rejection both start here.
#pragma once

#include "core/model/model.h"

namespace igms {

// centre and half extents, shape frame. A plane's is unbounded: half is zero and unused. A mesh's
// covers its surface samples and triangles (zero without either).
void boundingBox(const CollisionShape& s, Vector3& centre, Vector3& half);
// The radius of a sphere about that box's centre that holds the shape: a sphere's own, a capsule's
// or cylinder's tight one, else the box's half diagonal.
double boundingRadius(const CollisionShape& s);

}  // namespace igms
