// Composite-rigid-body algorithm (Featherstone, RBDA section 6.2), in world
// axes: with every body's inertia and motion subspace expressed in the world
// frame, composite inertias are plain sums and
//   H_ji = S_j^T Ic_i S_i   for j = i or j an ancestor of i,
// a dot product per entry, with no force carried from body to body.
#include "core/dynamics/crba.h"

#include "core/model/joint.h"

namespace igms {

const MatrixX& crba(const Model& model, Data& data, const VectorX& q) {
  for (int i = 0; i < model.nb; ++i) data.liMi[i] = jointPlacement(model, i, q);
  return crbaAtPlacements(model, data);
}

const MatrixX& crbaAtPlacements(const Model& model, Data& data) {
  // World poses, world inertias, world motion subspaces.
  for (int i = 0; i < model.nb; ++i) {
    const int p = model.parent[i];
    data.oMi[i] = p < 0 ? data.liMi[i] : data.oMi[p] * data.liMi[i];
    data.Ic[i] = model.inertia[i].transformedBy(data.oMi[i]);
    for (int k = 0; k < model.joint_nv[i]; ++k)
      data.S_world[model.v_index[i] + k] = data.oMi[i].act(subspaceColumn(model, i, k));
  }
  // Composite inertias: children add into parents.
  for (int i = model.nb - 1; i >= 0; --i)
    if (model.parent[i] >= 0) data.Ic[model.parent[i]] += data.Ic[i];

  MatrixX& H = data.H;
  for (int i = model.nb - 1; i >= 0; --i) {
    const int ci = model.v_index[i];
    for (int k = 0; k < model.joint_nv[i]; ++k) {
      const Force F = data.Ic[i] * data.S_world[ci + k];
      // H_ji for every dof j of body i and of its ancestors.
      for (int j = i; j >= 0; j = model.parent[j]) {
        const int cj = model.v_index[j];
        const int nj = j == i ? k + 1 : model.joint_nv[j];
        for (int r = 0; r < nj; ++r) H(cj + r, ci + k) = H(ci + k, cj + r) = F.dot(data.S_world[cj + r]);
      }
    }
  }
  return H;
}

}  // namespace igms
