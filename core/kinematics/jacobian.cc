#include "core/kinematics/jacobian.h"

#include "core/kinematics/forward_kinematics.h"
#include "core/model/joint.h"

namespace igms {

void pointJacobian(const Model& model, const Data& data, int frame, const Vector3& point_in_frame, Matrix6X& J) {
  J.setZero();
  const Frame& fr = model.frame(frame);
  const Vector3 p_W = framePose(model, data, frame).act(point_in_frame);
  for (int j = fr.body; j >= 0; j = model.parent[j]) {
    const SE3& oMj = data.oMi[j];
    for (int k = 0; k < model.joint_nv[j]; ++k) {
      // S_j column seen in world axes at the world origin, then moved to the point.
      const Motion s = oMj.act(subspaceColumn(model, j, k));
      auto col = J.col(model.v_index[j] + k);
      col.head<3>() = s.v + s.w.cross(p_W);
      col.tail<3>() = s.w;
    }
  }
}

void frameJacobian(const Model& model, Data& data, const VectorX& q, int frame, Matrix6X& J) {
  // Only the frame's support moves it: on a humanoid's hand that is 8 of 32 bodies.
  int depth = 0;
  for (int j = model.frame(frame).body; j >= 0; j = model.parent[j]) data.support[depth++] = j;
  while (depth > 0) placeBody(model, data, data.support[--depth], q);
  pointJacobian(model, data, frame, Vector3::Zero(), J);
}

Vector6 pointBiasAcceleration(const Model& model, Data& data, const VectorX& q, const VectorX& v, int frame,
                              const Vector3& point_in_frame) {
  const Frame& fr = model.frame(frame);
  // Outward pass with qdd = 0 and no gravity: a_i = X a_p + v_i x vJ.
  for (int i = 0; i <= fr.body; ++i) {
    placeBody(model, data, i, q);
    const int p = model.parent[i];
    const Motion vJ = jointMotion(model, i, v);
    if (p < 0) {
      data.v[i] = vJ;
      data.a[i] = Motion::Zero();
    } else {
      data.v[i] = data.liMi[i].actInv(data.v[p]) + vJ;
      data.a[i] = data.liMi[i].actInv(data.a[p]) + data.v[i].cross(vJ);
    }
  }
  Vector6 out = Vector6::Zero();
  if (fr.body < 0) return out;
  const SE3& oMb = data.oMi[fr.body];
  const Vector3 r = fr.placement.act(point_in_frame);  // point in body coordinates
  const Motion& vb = data.v[fr.body];
  const Motion& ab = data.a[fr.body];
  const Vector3 v_pt = vb.v + vb.w.cross(r);
  const Vector3 a_pt = ab.v + ab.w.cross(r) + vb.w.cross(v_pt);  // spatial -> classical
  out.head<3>() = oMb.R * a_pt;
  out.tail<3>() = oMb.R * ab.w;
  return out;
}

}  // namespace igms
