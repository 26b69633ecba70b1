// Forward kinematics of every body and every frame (URDF link).
#pragma once

#include <vector>

#include "core/model/data.h"
#include "core/model/joint.h"

namespace igms {

// Body i at q: its placement in its parent (data.liMi[i]) and its world pose
// (data.oMi[i], from its parent's, which must be placed already).
inline void placeBody(const Model& model, Data& data, int i, const VectorX& q) {
  placeJoint(model, i, q, data.liMi[i]);
  const int p = model.parent[i];
  data.oMi[i] = p < 0 ? data.liMi[i] : data.oMi[p] * data.liMi[i];
}

// \return nothing; data.liMi, data.oMi (bodies) and data.oMf (frames) hold the poses.
void forwardKinematics(const Model& model, Data& data, const VectorX& q);

// Poses of the bodies only (data.liMi, data.oMi); frames untouched.
void bodyKinematics(const Model& model, Data& data, const VectorX& q);

// Every frame's velocity at (q, v), world axes: the linear velocity of its origin and its angular
// velocity (a frame fixed to the world: zero). bodyKinematics must have run at q; data.v holds the
// bodies' velocities after.
void frameVelocities(const Model& model, Data& data, const VectorX& v, std::vector<Motion>& out);

// World pose of frame f from data.oMi (bodyKinematics must have run at this q).
inline SE3 framePose(const Model& model, const Data& data, int f) {
  const Frame& fr = model.frame(f);
  return fr.body < 0 ? fr.placement : data.oMi[static_cast<size_t>(fr.body)] * fr.placement;
}

}  // namespace igms
