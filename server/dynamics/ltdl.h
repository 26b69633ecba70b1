// Sparse L^T D L factorisation of the joint-space inertia matrix H along the
// tree (Featherstone, RBDA section 6.5): fill-in stays within each dof's
// ancestors, so a branched tree factorises in O(n d^2), d the depth.
#pragma once

#include <vector>

#include "server/model/data.h"

namespace igms {

// Factorises the lower triangle of H in place into unit-lower L (strictly
// below the diagonal) and D (on the diagonal), H = L^T D L. dof_parent[k] is
// the nearest ancestor dof of k (-1 at a root).
// \return -1 on success, otherwise the first dof whose pivot vanished
// (below kSingularPivot of its diagonal) or is not finite: H is singular there.
// diag: scratch of size nv (keeps the original diagonal).
int ltdlFactor(const std::vector<int>& dof_parent, MatrixX& H, VectorX& diag);

// A pivot below this fraction of its original diagonal entry counts as zero.
constexpr double kSingularPivot = 1e-13;

// Solves H x = b in place (b becomes x) with the factors from ltdlFactor.
void ltdlSolve(const std::vector<int>& dof_parent, const MatrixX& LD, VectorX& b);

}  // namespace igms
