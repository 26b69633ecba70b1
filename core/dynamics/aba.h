// Articulated-body algorithm: O(n) forward dynamics (Featherstone, RBDA
// section 7.3), the choice for large trees. Same result as forwardDynamics.
#pragma once

#include <vector>

#include "core/model/data.h"

namespace igms {

// \return true and data.qdd; false when an articulated inertia along a joint
// vanishes (H singular), with data.singular_dof naming the dof.
bool aba(const Model& model, Data& data, const VectorX& q, const VectorX& v, const VectorX& tau,
         const std::vector<Force>* fext = nullptr);

}  // namespace igms
