#include "core/kinematics/forward_kinematics.h"

namespace igms {

void bodyKinematics(const Model& model, Data& data, const VectorX& q) {
  for (int i = 0; i < model.nb; ++i) placeBody(model, data, i, q);
}

void forwardKinematics(const Model& model, Data& data, const VectorX& q) {
  bodyKinematics(model, data, q);
  for (size_t f = 0; f < model.frames.size(); ++f) data.oMf[f] = framePose(model, data, static_cast<int>(f));
}

void frameVelocities(const Model& model, Data& data, const VectorX& v, std::vector<Motion>& out) {
  for (int i = 0; i < model.nb; ++i) {
    const int p = model.parent[i];
    const Motion vJ = jointMotion(model, i, v);
    data.v[i] = p < 0 ? vJ : data.liMi[i].actInv(data.v[p]) + vJ;
  }
  for (size_t f = 0; f < model.frames.size(); ++f) {
    const Frame& fr = model.frame(static_cast<int>(f));
    if (fr.body < 0) {
      out[f] = Motion::Zero();
      continue;
    }
    const Motion& vb = data.v[static_cast<size_t>(fr.body)];
    const Matrix3& R = data.oMi[static_cast<size_t>(fr.body)].R;
    out[f] = Motion{R * (vb.v + vb.w.cross(fr.placement.p)), R * vb.w};
  }
}

}  // namespace igms
