// Spatial algebra in body coordinates, the small set of operations the
// recursive algorithms need.
//
// Ordering follows Pinocchio: a motion vector is [v; w] (linear velocity of the
// frame origin, angular velocity), a force vector is [f; n] (force, moment about
// the frame origin). Both are expressed in the frame they are attached to.
//
//   SE3 M_AB = (R, p): pose of frame B in frame A, x_A = R x_B + p.
//   M.actInv(m_A) -> the same motion seen at B, in B coordinates (Featherstone's BX_A m).
//   M.act(f_B)    -> the same force seen at A, in A coordinates (BX_A^T f).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace igms {

using Vector3 = Eigen::Vector3d;
using Matrix3 = Eigen::Matrix3d;
using Vector6 = Eigen::Matrix<double, 6, 1>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

inline Matrix3 skew(const Vector3& a) {
  Matrix3 S;
  S << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return S;
}

struct Motion {
  Vector3 v = Vector3::Zero();  // linear velocity of the frame origin
  Vector3 w = Vector3::Zero();  // angular velocity

  static Motion Zero() { return Motion{}; }
  Motion operator+(const Motion& o) const { return {v + o.v, w + o.w}; }
  Motion& operator+=(const Motion& o) { v += o.v; w += o.w; return *this; }
  Motion operator*(double s) const { return {v * s, w * s}; }
  // Spatial cross product m x o (motion on motion).
  Motion cross(const Motion& o) const { return {w.cross(o.v) + v.cross(o.w), w.cross(o.w)}; }
  Vector6 toVector() const { Vector6 x; x << v, w; return x; }
  static Motion fromVector(const Vector6& x) { return {x.head<3>(), x.tail<3>()}; }
};

struct Force {
  Vector3 f = Vector3::Zero();  // force
  Vector3 n = Vector3::Zero();  // moment about the frame origin

  static Force Zero() { return Force{}; }
  Force operator+(const Force& o) const { return {f + o.f, n + o.n}; }
  Force operator-(const Force& o) const { return {f - o.f, n - o.n}; }
  Force& operator+=(const Force& o) { f += o.f; n += o.n; return *this; }
  Force& operator-=(const Force& o) { f -= o.f; n -= o.n; return *this; }
  Vector6 toVector() const { Vector6 x; x << f, n; return x; }
  double dot(const Motion& m) const { return f.dot(m.v) + n.dot(m.w); }
};

// Spatial cross product m x* f (motion on force).
inline Force crossForce(const Motion& m, const Force& f) {
  return {m.w.cross(f.f), m.w.cross(f.n) + m.v.cross(f.f)};
}

struct SE3 {
  Matrix3 R = Matrix3::Identity();
  Vector3 p = Vector3::Zero();

  static SE3 Identity() { return SE3{}; }
  SE3 operator*(const SE3& o) const { return {R * o.R, R * o.p + p}; }
  SE3 inverse() const { return {R.transpose(), -(R.transpose() * p)}; }
  Vector3 act(const Vector3& x) const { return R * x + p; }

  // Motion given at A (this is M_AB) re-expressed at B.
  Motion actInv(const Motion& m) const {
    return {R.transpose() * (m.v + m.w.cross(p)), R.transpose() * m.w};
  }
  // Motion given at B re-expressed at A.
  Motion act(const Motion& m) const {
    const Vector3 w = R * m.w;
    return {R * m.v + p.cross(w), w};
  }
  // Force given at B re-expressed at A.
  Force act(const Force& f) const {
    const Vector3 fA = R * f.f;
    return {fA, R * f.n + p.cross(fA)};
  }
  // Force given at A re-expressed at B.
  Force actInv(const Force& f) const {
    return {R.transpose() * f.f, R.transpose() * (f.n - p.cross(f.f))};
  }
};

// Rigid-body inertia about the frame origin: mass m, first moment h = m c
// (c the centre of mass), rotational inertia Io about the origin.
struct SpatialInertia {
  double m = 0.0;
  Vector3 h = Vector3::Zero();
  Matrix3 Io = Matrix3::Zero();

  static SpatialInertia Zero() { return SpatialInertia{}; }
  // From mass, centre of mass and the inertia about the centre of mass.
  static SpatialInertia fromMassComInertia(double m, const Vector3& c, const Matrix3& Ic) {
    const Matrix3 C = skew(c);
    return {m, m * c, Ic - m * C * C};
  }
  Vector3 com() const { return m > 0.0 ? Vector3(h / m) : Vector3::Zero(); }
  Matrix3 inertiaAboutCom() const {
    const Matrix3 C = skew(com());
    return Io + m * C * C;
  }

  SpatialInertia& operator+=(const SpatialInertia& o) { m += o.m; h += o.h; Io += o.Io; return *this; }

  Force operator*(const Motion& x) const {
    return {m * x.v - h.cross(x.w), Io * x.w + h.cross(x.v)};
  }

  // The same inertia expressed in frame A, given M = M_AB and this in B.
  //   Io' = R Io R^T - [p]x[Rh]x - [Rh]x[p]x - m [p]x[p]x, with
  //   [a]x[b]x = b a^T - (a.b) 1, so the shift is a few rank-one updates.
  SpatialInertia transformedBy(const SE3& M) const {
    SpatialInertia out;
    transformInto(M, out);
    return out;
  }
  // The same written into out (in place: a returned inertia copied into Data is read back before
  // its stores retire, a stall on every body; out must not be this).
  void transformInto(const SE3& M, SpatialInertia& out) const {
    const Matrix3& R = M.R;
    const Vector3 a = R * h;
    const Vector3& p = M.p;
    const Matrix3 T = R * Io;  // then R Io R^T = T R^T, symmetric: six entries
    const double diag = 2.0 * a.dot(p) + m * p.squaredNorm();
    // The six entries in registers first, each matrix entry stored once: writing both triangles
    // and then adding the diagonal in place reads back stores still in flight.
    double u[6];
    for (int r = 0, k = 0; r < 3; ++r)
      for (int c = r; c < 3; ++c, ++k)
        u[k] = T(r, 0) * R(c, 0) + T(r, 1) * R(c, 1) + T(r, 2) * R(c, 2) - a[r] * p[c] - p[r] * a[c] - m * p[r] * p[c];
    Matrix3& I = out.Io;
    I(0, 0) = u[0] + diag;
    I(0, 1) = I(1, 0) = u[1];
    I(0, 2) = I(2, 0) = u[2];
    I(1, 1) = u[3] + diag;
    I(1, 2) = I(2, 1) = u[4];
    I(2, 2) = u[5] + diag;
    out.m = m;
    out.h = a + m * p;
  }

  Matrix6 matrix() const {
    Matrix6 I;
    I.topLeftCorner<3, 3>() = m * Matrix3::Identity();
    I.topRightCorner<3, 3>() = -skew(h);
    I.bottomLeftCorner<3, 3>() = skew(h);
    I.bottomRightCorner<3, 3>() = Io;
    return I;
  }
};

// URDF-style pose: translation xyz, rotation R = Rz(yaw) Ry(pitch) Rx(roll).
inline SE3 fromXyzRpy(const Vector3& xyz, const Vector3& rpy) {
  return {(Eigen::AngleAxisd(rpy[2], Vector3::UnitZ()) * Eigen::AngleAxisd(rpy[1], Vector3::UnitY()) *
           Eigen::AngleAxisd(rpy[0], Vector3::UnitX()))
              .toRotationMatrix(),
          xyz};
}

// Y += X^T I X for a 6x6 symmetric inertia I given in B, with M = M_AB: the same
// articulated inertia expressed in A, added into Y (in place: no 6x6 returned
// and copied). Only I's upper triangle is read and both of Y's are written.
inline void addInertiaToParent(const SE3& M, const Matrix6& I, Matrix6& Y) {
  const Matrix3& R = M.R;
  // Rotate the blocks into A's orientation; A and C are symmetric: R X R^T from six dot products.
  const Matrix3 TA = R * I.topLeftCorner<3, 3>();
  const Matrix3 TC = R * I.bottomRightCorner<3, 3>();
  Matrix3 A, C;
  for (int r = 0; r < 3; ++r)
    for (int c = r; c < 3; ++c) {
      A(r, c) = A(c, r) = TA.row(r).dot(R.row(c));
      C(r, c) = C(c, r) = TC.row(r).dot(R.row(c));
    }
  const Matrix3 B = R * I.topRightCorner<3, 3>() * R.transpose();
  // Shift the reference point by p: T Y T^T with T = [[1, 0], [P, 1]], P = [p]x. Products with P
  // are cross products column by column (P X).col(j) = p x X.col(j), and A P = -(P A)^T (A symmetric).
  const Vector3& p = M.p;
  const auto crossColumns = [&p](const Matrix3& X) {
    Matrix3 out;
    for (int j = 0; j < 3; ++j) out.col(j) = p.cross(X.col(j));
    return out;
  };
  const Matrix3 PA = crossColumns(A);
  const Matrix3 B2 = B + PA.transpose();  // B + A P^T = B - A P = B + (P A)^T
  const Matrix3 PB = crossColumns(B);
  // C + P B - B^T P - P A P = C + PB + PB^T - P A P, and P A P = -P (P A)^T: symmetric.
  const Matrix3 C2 = C + PB + PB.transpose() + crossColumns(PA.transpose());
  Y.topLeftCorner<3, 3>() += A;
  Y.topRightCorner<3, 3>() += B2;
  Y.bottomLeftCorner<3, 3>() += B2.transpose();
  Y.bottomRightCorner<3, 3>() += C2;
}

}  // namespace igms
