#include "core/simulation/joint_limits.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "core/dynamics/crba.h"

namespace igms {

JointLimits::JointLimits(const Model& m, const VectorX& q_reference, bool enabled) {
  if (!enabled) return;
  for (int j = 0; j < m.nb; ++j) {
    if (m.joint_nv[static_cast<size_t>(j)] != 1) continue;  // the floating base has none
    const int v = m.v_index[static_cast<size_t>(j)];
    const double lo = m.lower[static_cast<size_t>(v)], hi = m.upper[static_cast<size_t>(v)];
    if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi)) continue;
    joints_.push_back({m.q_index[static_cast<size_t>(j)], v, lo, hi, 0.0, 0.0});
  }
  if (joints_.empty()) return;
  VectorX q = q_reference;
  for (const Joint& j : joints_) q[j.q] = std::clamp(q[j.q], j.lower, j.upper);
  Data d(m);
  const TreeMatrix& H = crba(m, d, q);
  // H^-1's diagonal, block by block of the tree matrix (a robot's block, not a pile's 6000 dofs).
  VectorX Hinv_diag = VectorX::Zero(m.nv);
  for (int b = 0; b < H.blocks(); ++b) {
    const int begin = H.blockBegin(b), n = H.blockEnd(b) - begin;
    const MatrixX block = H.block(begin, n);
    Hinv_diag.segment(begin, n) = block.ldlt().solve(MatrixX::Identity(n, n)).diagonal();
  }
  for (Joint& j : joints_) {
    const double mobility = Hinv_diag[j.v];  // 1 / the inertia the joint feels with the others free
    j.k = kOmega * kOmega / mobility;
    j.b = 2.0 * kOmega / mobility;
  }
}

void JointLimits::apply(const VectorX& q, const VectorX& v, VectorX& tau, VectorX& k, VectorX& b) const {
  for (const Joint& j : joints_) {
    k[j.v] = 0.0;
    b[j.v] = 0.0;
    const double x = q[j.q];
    double beyond = 0.0, back = 0.0;  // how far beyond, and the direction back into the range
    if (x > j.upper) {
      beyond = x - j.upper;
      back = -1.0;
    } else if (x < j.lower) {
      beyond = j.lower - x;
      back = 1.0;
    } else {
      continue;
    }
    const double push = j.k * beyond - j.b * back * v[j.v];  // the spring, and the damper on the speed into it
    if (push <= 0.0) continue;
    tau[j.v] += back * push;
    k[j.v] = j.k;
    b[j.v] = j.b;
  }
}

}  // namespace igms
