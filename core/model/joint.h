// Joint kinematics: the placement a joint gives its body, its velocity and its
// motion subspace S (the paper's iZ_i for a revolute joint). Small inline
// helpers, so the recursive algorithms read like the paper.
#pragma once

#include <Eigen/Geometry>
#include <cmath>

#include "core/model/model.h"

namespace igms {

// Body i in its parent body frame for coordinates q (iR_p^T and iP_i).
template <typename Q>
inline SE3 jointPlacement(const Model& m, int i, const Q& q) {
  const SE3& X = m.X_tree[i];
  const int iq = m.q_index[i];
  switch (m.joint_type[i]) {
    case JointType::Revolute: {
      // Axis-aligned joints (most robots) rotate two columns of X.R only.
      const int k = m.axis_aligned[i];
      if (k < 0) return {X.R * Eigen::AngleAxisd(q[iq], m.axis[i]).toRotationMatrix(), X.p};
      const double angle = m.axis[i][k] * q[iq];  // axis is +-e_k
      const double c = std::cos(angle), s = std::sin(angle);
      const int a = (k + 1) % 3, b = (k + 2) % 3;  // R_k(angle) e_a = c e_a + s e_b
      SE3 out{X.R, X.p};
      out.R.col(a) = c * X.R.col(a) + s * X.R.col(b);
      out.R.col(b) = c * X.R.col(b) - s * X.R.col(a);
      return out;
    }
    case JointType::Prismatic:
      return {X.R, X.p + X.R * (m.axis[i] * q[iq])};
    case JointType::Floating: {
      Eigen::Quaterniond quat(q[iq + 3], q[iq + 4], q[iq + 5], q[iq + 6]);  // w first
      quat.normalize();
      return {quat.toRotationMatrix(), Vector3(q[iq], q[iq + 1], q[iq + 2])};
    }
  }
  return X;
}

// S_i qdot_i: the joint's contribution to the body velocity, body coordinates.
template <typename V>
inline Motion jointMotion(const Model& m, int i, const V& v) {
  const int iv = m.v_index[i];
  switch (m.joint_type[i]) {
    case JointType::Revolute: return {Vector3::Zero(), m.axis[i] * v[iv]};
    case JointType::Prismatic: return {m.axis[i] * v[iv], Vector3::Zero()};
    case JointType::Floating: return {Vector3(v[iv], v[iv + 1], v[iv + 2]), Vector3(v[iv + 3], v[iv + 4], v[iv + 5])};
  }
  return {};
}

// Column k of S_i.
inline Motion subspaceColumn(const Model& m, int i, int k) {
  switch (m.joint_type[i]) {
    case JointType::Revolute: return {Vector3::Zero(), m.axis[i]};
    case JointType::Prismatic: return {m.axis[i], Vector3::Zero()};
    case JointType::Floating: {
      Vector6 e = Vector6::Zero();
      e[k] = 1.0;
      return Motion::fromVector(e);
    }
  }
  return {};
}

// S_i^T f, written into out[0 .. nv_i).
template <typename Out>
inline void projectOnSubspace(const Model& m, int i, const Force& f, Out&& out) {
  switch (m.joint_type[i]) {
    case JointType::Revolute: out[0] = m.axis[i].dot(f.n); return;
    case JointType::Prismatic: out[0] = m.axis[i].dot(f.f); return;
    case JointType::Floating:
      for (int k = 0; k < 3; ++k) { out[k] = f.f[k]; out[k + 3] = f.n[k]; }
      return;
  }
}

}  // namespace igms
