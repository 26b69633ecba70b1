#include "core/kinematics/forward_kinematics.h"

namespace igms {

void bodyKinematics(const Model& model, Data& data, const VectorX& q) {
  for (int i = 0; i < model.nb; ++i) placeBody(model, data, i, q);
}

void forwardKinematics(const Model& model, Data& data, const VectorX& q) {
  bodyKinematics(model, data, q);
  for (size_t f = 0; f < model.frames.size(); ++f) data.oMf[f] = framePose(model, data, static_cast<int>(f));
}

}  // namespace igms
