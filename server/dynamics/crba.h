// Composite-rigid-body algorithm: the joint-space inertia matrix H(q).
#pragma once

#include "server/model/data.h"

namespace igms {

// \return data.H (nv x nv, symmetric, both triangles filled). Also leaves
// data.liMi and data.Ic (composite inertias) at q.
const MatrixX& crba(const Model& model, Data& data, const VectorX& q);

}  // namespace igms
