// Push (Son et al. 2003, eq. 3): the tip penetrates a link by d; the contact
// force on the link is c = k_p d, along the inward normal, and enters the
// forward dynamics as U_E = J^T c (an external point force, see rnea).
// With the virtual coupling's damper (Colgate et al. 1995), c = k_p d + b d', d' the rate at
// which the tip goes in; never below zero: the coupling pushes, it does not hold the hand back.
#pragma once

#include "core/geometry/tip_contact.h"

namespace igms {

struct PushForce {
  Vector3 on_link = Vector3::Zero();  // N, world: -k_p d n (into the link)
  Vector3 point = Vector3::Zero();    // world
  bool clamped = false;               // |c| limited to max_force
  bool slack = false;                 // touching, but the damper cancels the spring: c = 0
};

// c = k_p d + b d', at least 0, capped at max_force N. depth_rate: d' (m/s, positive going in).
inline PushForce pushForce(const TipContact& contact, double k_p, double max_force, double b = 0.0,
                           double depth_rate = 0.0) {
  PushForce out;
  if (!contact.touching) return out;
  double magnitude = k_p * contact.depth + b * depth_rate;
  if (magnitude <= 0.0) {  // the tip leaves faster than the spring relaxes: no force, no gradient
    out.slack = true;
    out.point = contact.point;
    return out;
  }
  if (magnitude > max_force) {
    magnitude = max_force;
    out.clamped = true;
  }
  out.on_link = -magnitude * contact.normal;
  out.point = contact.point;
  return out;
}

}  // namespace igms
