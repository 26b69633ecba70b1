// What a scene says about contact: the materials that touch, and the solver's
// knobs. Plain values: the scene reads them, the contact layer uses them.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>

namespace igms {

struct Material {
  double friction = 1.0;     // Coulomb coefficient mu (the cone |f_t| <= mu f_n)
  double restitution = 0.0;  // Newton's e: the normal speed after an impact is e times the speed before
  // Resistance at a single point of contact (a ball, a capsule's end), as MuJoCo's condim 6: a torque
  // of at most coefficient x normal force opposes rolling (about the tangents) and spinning (about the
  // normal); inside that, it holds. Lengths, m. A patch's torsion comes from its area instead.
  double rolling = 0.0;
  double torsion = 0.0;
};

// Two materials in contact: friction the geometric mean (a slippery side makes the pair slippery;
// equal materials keep their own), restitution the larger (a steel ball bounces off wood), rolling
// and torsional resistance the larger (a ball on a carpet: the carpet's).
inline Material combine(const Material& a, const Material& b) {
  return Material{std::sqrt(a.friction * b.friction), std::max(a.restitution, b.restitution),
                  std::max(a.rolling, b.rolling), std::max(a.torsion, b.torsion)};
}

struct ContactSettings {
  bool self_collision = false;    // a robot's links against each other (adjacent links never)
  double margin = 0.005;          // m: pairs closer than this are contacts, checked so that they do not cross
  int iterations = 100;           // the solver's sweeps at most
  double tolerance = 1e-10;       // m/s: it stops when no sweep changes a contact velocity by more
  double bounce_velocity = 0.05;  // m/s: slower impacts do not bounce (resting contact stays at rest)
  int max_contacts = 0;           // contact points at most (0: from the scene's size)
};

}  // namespace igms
