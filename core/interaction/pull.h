// Pull (Son et al. 2003, eq. 4): the tip is tied to a point of the robot by a
// spring-damper, F = k (x_ph - x) + b (xd_ph - xd), applied at the point, so
// tau = J^T F. The paper prints "- b (xd_ph - xd)"; read literally that term
// injects energy (with the device held still it pushes the point along its own
// velocity), so we use the passive sign of Hogan's impedance control, which the
// paper cites for this law. The spring's stretch is capped so that a jump of
// the device cannot inject a huge force, and |F| is capped at max_force.
//
// In six dimensions (the paper's X_ph and X_endeff are poses, k and b 6x6) the
// grasped frame's orientation R is tied to the device's R_ph as well: the
// error is the rotation vector e = log(R_ph R^T) (world axes, on SO(3), not
// Euler angles), the torque k_r e + b_r (w_ph - w), e capped at max_angle and
// |torque| at max_torque. With k and b block-diagonal (translation and
// rotation uncoupled at the grasped point) the 6-D law is these two laws.
#pragma once

#include "core/model/model.h"

namespace igms {

// Scales x down to length max when it is longer. \return whether it did.
inline bool capLength(Vector3& x, double max) {
  const double n = x.norm();
  if (n <= max) return false;
  x *= max / n;
  return true;
}

struct PullForce {
  Vector3 on_robot = Vector3::Zero();  // N, world
  bool stretch_capped = false;
  bool clamped = false;
};

inline PullForce pullForce(double k, double b, double max_stretch, double max_force, const Vector3& x_ph,
                           const Vector3& xd_ph, const Vector3& x, const Vector3& xd) {
  PullForce out;
  Vector3 stretch = x_ph - x;
  out.stretch_capped = capLength(stretch, max_stretch);
  out.on_robot = k * stretch + b * (xd_ph - xd);
  out.clamped = capLength(out.on_robot, max_force);
  return out;
}

// The rotation vector of R (axis times angle, angle in [0, pi]): SO(3)'s log map.
inline Vector3 rotationLog(const Matrix3& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

struct PullTorque {
  Vector3 on_robot = Vector3::Zero();  // N m, world
  bool angle_capped = false;
  bool clamped = false;
};

// R_ph, R: world <- device, world <- grasped frame; w_ph, w: their angular velocities, world.
inline PullTorque pullTorque(double k_rot, double b_rot, double max_angle, double max_torque, const Matrix3& R_ph,
                             const Vector3& w_ph, const Matrix3& R, const Vector3& w) {
  PullTorque out;
  Vector3 e = rotationLog(R_ph * R.transpose());
  out.angle_capped = capLength(e, max_angle);
  out.on_robot = k_rot * e + b_rot * (w_ph - w);
  out.clamped = capLength(out.on_robot, max_torque);
  return out;
}

}  // namespace igms
