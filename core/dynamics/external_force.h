// External forces f_E of the paper: a force given in world axes acting at a
// point given in a link frame, turned into the wrench on the body, in body
// coordinates, that rnea and aba take.
#pragma once

#include <vector>

#include "core/model/data.h"

namespace igms {

struct PointForce {
  int frame = -1;                   // Model::frames index (any URDF link)
  Vector3 point = Vector3::Zero();  // in that link's frame, m
  Vector3 force = Vector3::Zero();  // world axes, N
  Vector3 torque = Vector3::Zero(); // world axes, N m (a pure moment on the link, e.g. the 6-D pull)
};

// fext[b] += wrench of pf on body b (nothing for a frame fixed to the world).
// Needs data.oMi at the current q.
inline void addPointForce(const Model& model, const Data& data, const PointForce& pf, std::vector<Force>& fext) {
  const Frame& fr = model.frame(pf.frame);
  if (fr.body < 0) return;
  const SE3& oMb = data.oMi[static_cast<size_t>(fr.body)];
  const Vector3 f_B = oMb.R.transpose() * pf.force;  // iR_0 0f_E
  const Vector3 c_B = fr.placement.act(pf.point);    // contact point in body coordinates
  fext[static_cast<size_t>(fr.body)] += Force{f_B, c_B.cross(f_B) + oMb.R.transpose() * pf.torque};
}

inline void clearExternalForces(std::vector<Force>& fext) {
  for (auto& f : fext) f = Force::Zero();
}

}  // namespace igms
