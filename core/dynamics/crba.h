// Composite-rigid-body algorithm: the joint-space inertia matrix H(q).
#pragma once

#include "core/model/data.h"

namespace igms {

// \return data.H (nv x nv, symmetric, both triangles filled; tree_matrix.h: its .dense() for a MatrixX). Also leaves
// data.liMi, data.oMi and data.Ic (composite inertias, world axes) at q.
const TreeMatrix& crba(const Model& model, Data& data, const VectorX& q);

// The same with data.liMi already at q (as rnea or bias leave it).
const TreeMatrix& crbaAtPlacements(const Model& model, Data& data);

// Only the upper triangle of data.H (with the diagonal), the part the LDL^T
// factorisation reads; the strictly lower part is left as it was.
void crbaUpperAtPlacements(const Model& model, Data& data);

// The same with data.oMi at q too (bodyKinematics ran): the world poses are not composed again.
void crbaUpperAtPoses(const Model& model, Data& data);

}  // namespace igms
