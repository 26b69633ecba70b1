// The device's workspace mapped into the scene: scene = offset + scale * device
// (the scene's interaction.workspace). Forces need no mapping: the axes agree.
#pragma once

#include "core/model/spatial.h"

namespace igms {

struct WorkspaceMap {
  double scale = 1.0;
  Vector3 offset = Vector3::Zero();
  Vector3 toScene(const Vector3& d) const { return offset + scale * d; }
  Vector3 toDevice(const Vector3& s) const { return (s - offset) / scale; }
};

}  // namespace igms
