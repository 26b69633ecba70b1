// Forward kinematics of every body and every frame (URDF link).
#pragma once

#include "core/model/data.h"

namespace igms {

// \return nothing; data.liMi, data.oMi (bodies) and data.oMf (frames) hold the poses.
void forwardKinematics(const Model& model, Data& data, const VectorX& q);

// Poses of the bodies only (data.liMi, data.oMi); frames untouched.
void bodyKinematics(const Model& model, Data& data, const VectorX& q);

// World pose of frame f from data.oMi (bodyKinematics must have run at this q).
inline SE3 framePose(const Model& model, const Data& data, int f) {
  const Frame& fr = model.frame(f);
  return fr.body < 0 ? fr.placement : data.oMi[static_cast<size_t>(fr.body)] * fr.placement;
}

}  // namespace igms
