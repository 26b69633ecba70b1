// Viscous joint damping from the URDF's <dynamics damping>: tau_d = -d qdot.
// (The URDF's Coulomb <friction> is kept in the model but not applied.)
// The one place igms spells it: the dynamics add it, a controller that
// compensates it adds its opposite, an implicit integrator puts h d on the
// diagonal.
#pragma once

#include "core/model/data.h"

namespace igms {

// d per joint coordinate (zero on a floating base).
inline Eigen::Map<const VectorX> jointDamping(const Model& model) {
  return Eigen::Map<const VectorX>(model.damping.data(), model.nv);
}

// tau -= d .* v: the damping torque acting on the joints.
inline void addJointDamping(const Model& model, const VectorX& v, VectorX& tau) {
  tau -= jointDamping(model).cwiseProduct(v);
}

}  // namespace igms
