// The tip sphere against every link's collision shapes: the deepest
// penetration, which is the push contact of eq. (3). One search, used by the
// server (against the exact state) and the client (against its estimate).
#pragma once

#include "core/geometry/tip_contact.h"

namespace igms {

struct LinkContact {
  TipContact contact;  // world
  int frame = -1;      // the touched link (-1: none)
};

// pose(f) -> SE3: the world pose of URDF link f. Links fixed to the world
// are never pushed. only_frame >= 0 searches that link alone. On equal depth
// the first link in frame order wins. Allocation-free.
template <typename PoseOfFrame>
LinkContact deepestContact(const Model& model, PoseOfFrame&& pose, const Vector3& tip, double tip_radius,
                           int only_frame = -1) {
  LinkContact best;
  for (size_t f = 0; f < model.frames.size(); ++f) {
    if (only_frame >= 0 && static_cast<int>(f) != only_frame) continue;
    const Frame& fr = model.frames[f];
    if (fr.body < 0 || fr.collisions.empty()) continue;
    const SE3 oMf = pose(static_cast<int>(f));
    for (const auto& shape : fr.collisions) {
      const TipContact c = tipContact(shape, oMf * shape.placement, tip, tip_radius);
      if (c.touching && c.depth > best.contact.depth) {
        best.contact = c;
        best.frame = static_cast<int>(f);
      }
    }
  }
  return best;
}

}  // namespace igms
