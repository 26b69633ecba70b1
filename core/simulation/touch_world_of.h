// The world a hand's proxy touches in a scene: every model frame with a
// collision shape, and the scene's solid geometry (solid obstacles, the
// ground). The server's simulation and the client's interaction build the
// same one from the same resolved scene.
#pragma once

#include "core/contact/contact_model.h"
#include "core/interaction/proxy.h"
#include "core/scene/resolved_scene.h"

namespace igms {

inline TouchWorld touchWorldOf(const ResolvedScene& r) {
  TouchWorld world(*r.model);
  for (const FixedGeom& g : solidGeometry(r)) world.addFixed(g.name, g.shape);
  return world;
}

}  // namespace igms
