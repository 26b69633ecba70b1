// Sparse L^T D L factorisation of the joint-space inertia matrix H along the
// tree (Featherstone, RBDA section 6.5): fill-in stays within each dof's
// ancestors, so a branched tree factorises in O(n d^2), d the depth.
#pragma once

#include <vector>

#include "core/model/data.h"

namespace igms {

// Factorises H in place, H = L^T D L: D on the diagonal, the unit-lower L
// stored transposed in the upper triangle (L(k, i) at H(i, k)). dof_parent[k] is
// the nearest ancestor dof of k (-1 at a root).
// \return -1 on success, otherwise the first dof whose pivot vanished
// (below kSingularPivot of its diagonal) or is not finite: H is singular there.
// run_start[j]: first dof of the run of consecutive ancestors ending at j
// (Model::dof_run_start). diag: scratch of size nv.
// factored (per block of H, or null): blocks that hold their factors already, left as they are.
int ltdlFactor(const std::vector<int>& dof_parent, const std::vector<int>& run_start, TreeMatrix& H, VectorX& diag,
               const std::vector<char>* factored = nullptr);
// The same for block b of H alone (its dofs reach no other block's).
int ltdlFactorBlock(const std::vector<int>& dof_parent, const std::vector<int>& run_start, TreeMatrix& H, VectorX& diag,
                    int b);

// A pivot below this fraction of its original diagonal entry counts as zero.
constexpr double kSingularPivot = 1e-13;

// Solves H x = b in place (b becomes x) with the factors from ltdlFactor.
void ltdlSolve(const std::vector<int>& dof_parent, const std::vector<int>& run_start, const TreeMatrix& LD, VectorX& b);

}  // namespace igms
