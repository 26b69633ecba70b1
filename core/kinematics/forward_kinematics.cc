#include "core/kinematics/forward_kinematics.h"

#include "core/model/joint.h"

namespace igms {

void bodyKinematics(const Model& model, Data& data, const VectorX& q) {
  for (int i = 0; i < model.nb; ++i) {
    placeJoint(model, i, q, data.liMi[i]);
    const int p = model.parent[i];
    data.oMi[i] = p < 0 ? data.liMi[i] : data.oMi[p] * data.liMi[i];
  }
}

void forwardKinematics(const Model& model, Data& data, const VectorX& q) {
  bodyKinematics(model, data, q);
  for (size_t f = 0; f < model.frames.size(); ++f) data.oMf[f] = framePose(model, data, static_cast<int>(f));
}

}  // namespace igms
