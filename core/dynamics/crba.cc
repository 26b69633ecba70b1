// Composite-rigid-body algorithm (Featherstone, RBDA section 6.2), in world
// axes: with every body's inertia and motion subspace expressed in the world
// frame, composite inertias are plain sums and
//   H_ji = S_j^T Ic_i S_i   for j = i or j an ancestor of i,
// a dot product per entry, with no force carried from body to body.
#include "core/dynamics/crba.h"

#include <cstddef>

#include "core/model/ancestor_runs.h"
#include "core/model/joint.h"

namespace igms {

const TreeMatrix& crba(const Model& model, Data& data, const VectorX& q) {
  for (int i = 0; i < model.nb; ++i) placeJoint(model, i, q, data.liMi[i]);
  return crbaAtPlacements(model, data);
}

const TreeMatrix& crbaAtPlacements(const Model& model, Data& data) {
  crbaUpperAtPlacements(model, data);
  // The mirror of the ancestor entries: every other entry is zero in both triangles, and stays so.
  // Column t's lower part is t's descendants, one contiguous range in depth-first order: the
  // stores run down a column (a row's would each touch another cache line).
  TreeMatrix& H = data.H;
  for (int b = 0; b < H.blocks(); ++b) {
    const std::ptrdiff_t stride = H.blockEnd(b) - H.blockBegin(b);  // from one column to the next
    for (int t = H.blockBegin(b); t < H.blockEnd(b); ++t) {
      double* const column = H.column(t);
      const double* const row = column + t;  // (t, c) is row[(c - t) stride]
      for (int c = t + 1; c < model.dof_subtree_end[t]; ++c) column[c] = row[(c - t) * stride];
    }
  }
  return H;
}

namespace {

// compose_world_poses: data.oMi from data.liMi here; else bodyKinematics left them (the same products).
void crbaUpper(const Model& model, Data& data, bool compose_world_poses) {
  // World poses, world inertias, world motion subspaces.
  for (int i = 0; i < model.nb; ++i) {
    const int p = model.parent[i];
    if (compose_world_poses) data.oMi[i] = p < 0 ? data.liMi[i] : data.oMi[p] * data.liMi[i];
    const SE3& oMi = data.oMi[i];
    // A free body (a floating joint with nothing below): its block of H is its own inertia in its own
    // frame, whatever its pose (S^T Ic S with S the unit twists of its frame); only S is needed here.
    const bool free_body = model.joint_type[i] == JointType::Floating && model.children[i].empty();
    if (!free_body) model.inertia[i].transformInto(oMi, data.Ic[i]);
    auto S = data.S_world.middleCols(model.v_index[i], model.joint_nv[i]);
    switch (model.joint_type[i]) {
      case JointType::Revolute: {
        const int k = model.axis_aligned[i];  // axis = +-e_k: a column of R, no product
        const Vector3 w = k >= 0 ? Vector3(model.axis[i][k] * oMi.R.col(k)) : Vector3(oMi.R * model.axis[i]);
        S.col(0) << oMi.p.cross(w), w;
        break;
      }
      case JointType::Prismatic: S.col(0) << oMi.R * model.axis[i], Vector3::Zero(); break;
      case JointType::Floating:
        // The unit twists of its frame, in world axes: along R's columns, and about them through p
        // (oMi.act of each, written out: a free body's six columns were a tenth of a pile's step).
        for (int k = 0; k < 3; ++k) {
          S.col(k) << oMi.R.col(k), Vector3::Zero();
          S.col(3 + k) << oMi.p.cross(oMi.R.col(k)), oMi.R.col(k);
        }
        break;
    }
  }
  // Composite inertias: children add into parents (a free body has neither).
  for (int i = model.nb - 1; i >= 0; --i)
    if (model.parent[i] >= 0) data.Ic[model.parent[i]] += data.Ic[i];

  // Column c of the upper triangle: S_j^T (Ic S_c) for c's own dof and every ancestor dof j, a dot
  // product each, written down the column's contiguous rows run by run.
  for (int i = model.nb - 1; i >= 0; --i) {
    if (model.joint_type[i] == JointType::Floating && model.children[i].empty()) {
      const SpatialInertia& I = model.inertia[i];
      const Matrix3 hx = skew(I.h);
      const int v0 = model.v_index[i];
      for (int c = 0; c < 6; ++c)
        for (int r = 0; r <= c; ++r) {
          double x;
          if (c < 3) x = r == c ? I.m : 0.0;              // m 1
          else if (r < 3) x = -hx(r, c - 3);               // -[h]x
          else x = I.Io(r - 3, c - 3);                     // Io
          data.H.column(v0 + c)[v0 + r] = x;
        }
      continue;
    }
    for (int k = 0; k < model.joint_nv[i]; ++k) {
      const int c = model.v_index[i] + k;
      const Force F = data.Ic[i] * Motion{data.S_world.col(c).head<3>(), data.S_world.col(c).tail<3>()};
      double* const column = data.H.column(c);
      const double* const S = data.S_world.data();  // 6 per dof: [v; w]
      forEachAncestorRun(model.dof_parent, model.dof_run_start, c, [&](int r, int j) {
        for (int t = r; t <= j; ++t) {
          const double* s = S + 6 * static_cast<std::ptrdiff_t>(t);
          column[t] = F.f[0] * s[0] + F.f[1] * s[1] + F.f[2] * s[2] + F.n[0] * s[3] + F.n[1] * s[4] + F.n[2] * s[5];
        }
      });
    }
  }
}

}  // namespace

void crbaUpperAtPlacements(const Model& model, Data& data) { crbaUpper(model, data, true); }

void crbaUpperAtPoses(const Model& model, Data& data) { crbaUpper(model, data, false); }

}  // namespace igms
