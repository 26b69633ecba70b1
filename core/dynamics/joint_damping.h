// Viscous joint damping from the URDF's <dynamics damping>: tau_d = -d qdot.
// (The URDF's Coulomb <friction> is kept in the model but not applied.)
#pragma once

#include "core/model/data.h"

namespace igms {

// tau -= d .* v over the joint coordinates (the floating base has none).
inline void addJointDamping(const Model& model, const VectorX& v, VectorX& tau) {
  for (int k = 0; k < model.nv; ++k) tau[k] -= model.damping[static_cast<size_t>(k)] * v[k];
}

}  // namespace igms
