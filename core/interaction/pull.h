// Pull (Son et al. 2003, eq. 4): the tip is tied to a point of the robot by a
// spring-damper, F = k (x_ph - x) + b (xd_ph - xd), applied at the point, so
// tau = J^T F. The paper prints "- b (xd_ph - xd)"; read literally that term
// injects energy (with the device held still it pushes the point along its own
// velocity), so we use the passive sign of Hogan's impedance control, which the
// paper cites for this law. The spring's stretch is capped so that a jump of
// the device cannot inject a huge force, and |F| is capped at max_force.
#pragma once

#include "core/model/model.h"

namespace igms {

struct PullForce {
  Vector3 on_robot = Vector3::Zero();  // N, world
  bool stretch_capped = false;
  bool clamped = false;
};

inline PullForce pullForce(double k, double b, double max_stretch, double max_force, const Vector3& x_ph,
                           const Vector3& xd_ph, const Vector3& x, const Vector3& xd) {
  PullForce out;
  Vector3 stretch = x_ph - x;
  const double len = stretch.norm();
  if (len > max_stretch) {
    stretch *= max_stretch / len;
    out.stretch_capped = true;
  }
  Vector3 F = k * stretch + b * (xd_ph - xd);
  const double n = F.norm();
  if (n > max_force) {
    F *= max_force / n;
    out.clamped = true;
  }
  out.on_robot = F;
  return out;
}

}  // namespace igms
