// Push (Son et al. 2003, eq. 3): the tip penetrates a link by d; the contact
// force on the link is c = k_p d, along the inward normal, and enters the
// forward dynamics as U_E = J^T c (an external point force, see rnea).
#pragma once

#include "core/geometry/tip_contact.h"

namespace igms {

struct PushForce {
  Vector3 on_link = Vector3::Zero();  // N, world: -k_p d n (into the link)
  Vector3 point = Vector3::Zero();    // world
  bool clamped = false;               // |c| limited to max_force
};

// c = k_p d, capped at max_force N.
inline PushForce pushForce(const TipContact& contact, double k_p, double max_force) {
  PushForce out;
  if (!contact.touching) return out;
  double magnitude = k_p * contact.depth;
  if (magnitude > max_force) {
    magnitude = max_force;
    out.clamped = true;
  }
  out.on_link = -magnitude * contact.normal;
  out.point = contact.point;
  return out;
}

}  // namespace igms
