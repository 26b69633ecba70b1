// Joint kinematics: the placement a joint gives its body, its velocity and its
// motion subspace S (the paper's iZ_i for a revolute joint). Small inline
// helpers, so the recursive algorithms read like the paper.
#pragma once

#include <Eigen/Geometry>
#include <cmath>

#include "core/model/model.h"
#include "core/model/sincos.h"

namespace igms {

namespace detail {
// out.R = X.R R_K(angle) for a joint about +-e_K, given c = cos, s = sin of the signed angle:
// columns A = K+1 and B = K+2 (mod 3) turn, column K stays. Indices fixed at compile time, each
// entry written once.
template <int K>
inline void rotateAboutAxis(const Matrix3& R, double c, double s, Matrix3& out) {
  constexpr int A = (K + 1) % 3, B = (K + 2) % 3;  // R_K(angle) e_A = c e_A + s e_B
  out.col(K) = R.col(K);
  out.col(A) = c * R.col(A) + s * R.col(B);
  out.col(B) = c * R.col(B) - s * R.col(A);
}
}  // namespace detail

// Body i in its parent body frame for coordinates q (iR_p^T and iP_i), written
// into out (in place: a returned pose copied into Data read back stores the
// CPU had not finished, a measurable stall on every joint).
template <typename Q>
inline void placeJoint(const Model& m, int i, const Q& q, SE3& out) {
  const SE3& X = m.X_tree[i];
  const int iq = m.q_index[i];
  switch (m.joint_type[i]) {
    case JointType::Revolute: {
      // Axis-aligned joints (most robots) rotate two columns of X.R only.
      const int k = m.axis_aligned[i];
      out.p = X.p;
      if (k < 0) {
        out.R.noalias() = X.R * Eigen::AngleAxisd(q[iq], m.axis[i]).toRotationMatrix();
        return;
      }
      const double angle = m.axis[i][k] * q[iq];  // axis is +-e_k
      double s, c;
      sinCos(angle, s, c);
      if (k == 0) detail::rotateAboutAxis<0>(X.R, c, s, out.R);
      else if (k == 1) detail::rotateAboutAxis<1>(X.R, c, s, out.R);
      else detail::rotateAboutAxis<2>(X.R, c, s, out.R);
      return;
    }
    case JointType::Prismatic:
      out.R = X.R;
      out.p = X.p + X.R * (m.axis[i] * q[iq]);
      return;
    case JointType::Floating: {
      Eigen::Quaterniond quat(q[iq + 3], q[iq + 4], q[iq + 5], q[iq + 6]);  // w first
      quat.normalize();
      out.R = quat.toRotationMatrix();
      out.p = Vector3(q[iq], q[iq + 1], q[iq + 2]);
      return;
    }
  }
  out = X;
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
