// The contacts of one step: a fixed-capacity buffer (no allocation in the
// step), in a fixed order (by geom pair, then by point), and what overflowed.
#pragma once

#include <cstdint>
#include <vector>

#include "core/model/spatial.h"

namespace igms {

struct Contact {
  int geom_a = -1, geom_b = -1;   // geom_a < geom_b (ContactModel::geoms())
  int body_a = -1, body_b = -1;   // -1: fixed to the world
  int slot = 0;                   // which of the pair's points
  Vector3 point = Vector3::Zero();      // world: midway between the surfaces
  Vector3 normal = Vector3::UnitZ();    // world, unit, from a toward b
  double distance = 0.0;                // m, signed at the step's start: negative where they overlap
  double friction = 0.0, restitution = 0.0;  // the pair's (combined) material
  double rolling = 0.0, torsion = 0.0;       // m: its rolling and torsional resistance (one point only)
  Vector3 impulse = Vector3::Zero();    // world, N s over the step: on b (a gets the opposite)
  Vector3 moment = Vector3::Zero();     // world, N m s about the point: rolling and torsional resistance, on b
};

struct ContactSet {
  std::vector<Contact> c;   // capacity entries, n in use
  int n = 0;
  int64_t dropped = 0;      // points that did not fit, since the start (counted, never silent)

  explicit ContactSet(int capacity = 0) : c(static_cast<size_t>(capacity)) {}
  int capacity() const { return static_cast<int>(c.size()); }
  const Contact& operator[](int k) const { return c[static_cast<size_t>(k)]; }
  Contact& operator[](int k) { return c[static_cast<size_t>(k)]; }
  // The deepest overlap in use (0 when none overlaps).
  double maxPenetration() const {
    double d = 0.0;
    for (int k = 0; k < n; ++k) d = std::min(d, c[static_cast<size_t>(k)].distance);
    return -d;
  }
};

}  // namespace igms
