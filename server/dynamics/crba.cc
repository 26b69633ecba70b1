// Composite-rigid-body algorithm (Featherstone, RBDA section 6.2).
//   Ic_i = I_i + sum over children j of jX_i^T Ic_j jX_i
//   H_ii = S_i^T Ic_i S_i, H_ji = S_j^T (jX_i^T Ic_i S_i) for every ancestor j.
#include "server/dynamics/crba.h"

#include "server/model/joint.h"

namespace igms {
namespace {

// F = Ic S_i (6 x nv_i), written into the columns of data.F.
void compositeTimesSubspace(const Model& model, int i, const SpatialInertia& Ic, Matrix6X& F) {
  const int c0 = model.v_index[i];
  for (int k = 0; k < model.joint_nv[i]; ++k) {
    const Force f = Ic * subspaceColumn(model, i, k);
    F.col(c0 + k) << f.f, f.n;
  }
}

}  // namespace

const MatrixX& crba(const Model& model, Data& data, const VectorX& q) {
  for (int i = 0; i < model.nb; ++i) {
    data.liMi[i] = jointPlacement(model, i, q);
    data.Ic[i] = model.inertia[i];
  }
  MatrixX& H = data.H;
  Matrix6X& F = data.F;
  for (int i = model.nb - 1; i >= 0; --i) {
    const int ci = model.v_index[i];
    const int ni = model.joint_nv[i];
    compositeTimesSubspace(model, i, data.Ic[i], F);
    // Carry F = Ic_i S_i up the tree, projecting on each ancestor's subspace.
    for (int j = i;;) {
      const int cj = model.v_index[j];
      for (int k = 0; k < ni; ++k) {
        const Force f{F.col(ci + k).head<3>(), F.col(ci + k).tail<3>()};
        Eigen::Matrix<double, 6, 1> proj;
        projectOnSubspace(model, j, f, proj);
        for (int r = 0; r < model.joint_nv[j]; ++r) {
          H(cj + r, ci + k) = proj[r];
          H(ci + k, cj + r) = proj[r];
        }
      }
      const int p = model.parent[j];
      if (p < 0) break;
      for (int k = 0; k < ni; ++k) {
        const Force f = data.liMi[j].act(Force{F.col(ci + k).head<3>(), F.col(ci + k).tail<3>()});
        F.col(ci + k) << f.f, f.n;
      }
      j = p;
    }
    const int p = model.parent[i];
    if (p >= 0) data.Ic[p] += data.Ic[i].transformedBy(data.liMi[i]);
  }
  return H;
}

}  // namespace igms
