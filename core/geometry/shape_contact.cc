#include "core/geometry/shape_contact.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/geometry/convex_distance.h"
#include "core/geometry/mesh_query.h"
#include "core/geometry/point_query.h"

namespace igms {
namespace {

constexpr int kRimPoints = 8;              // per cylinder cap
constexpr int kMaxCandidates = 512 + 64;   // a mesh's samples (mesh_samples.h caps them at 512) and a few more
constexpr double kSamePoint = 1e-6;        // m: two candidates closer than this are one
constexpr double kFacing = 0.99619469809;  // cos 5 deg: a cylinder's cap this near facing a contact lies on it

using Kind = CollisionShape::Kind;

// Raw storage (Eigen's vectors are left uninitialised): a pair's call must not clear 30 kB first.
struct Candidate {
  Vector3 point, normal;
  double distance;
};

struct Candidates {
  Candidate p[kMaxCandidates];
  int n = 0;
  void add(const Vector3& on_a, const Vector3& on_b, const Vector3& normal, double distance) {
    if (n < kMaxCandidates) p[n++] = Candidate{0.5 * (on_a + on_b), normal, distance};
  }
};

// A shape's points that may touch: (point, radius) in world, a radius rounding it (capsule ends).
// A cylinder's rim points only where a cap faces `toward` (within kFacing; zero: always): a cap lying
// flat touches by its rim, but a cylinder rolling on its side would meet its rim points as they come
// round, and check each one (a ghost contact, braking the roll) before the exact lowest rim point,
// which extremeRimPoints gives, reached it. \return how many were written (at most 2 kRimPoints + 2).
int featurePoints(const CollisionShape& s, const SE3& pose, Vector3* pts, double* radius,
                  const Vector3& toward = Vector3::Zero()) {
  int n = 0;
  switch (s.kind) {
    case Kind::Box: {
      const Vector3 h = 0.5 * s.size;
      for (int c = 0; c < 8; ++c) {
        pts[n] = pose.act(Vector3((c & 1) ? h.x() : -h.x(), (c & 2) ? h.y() : -h.y(), (c & 4) ? h.z() : -h.z()));
        radius[n++] = 0.0;
      }
      break;
    }
    case Kind::Cylinder: {
      const double r = s.size[0], hl = 0.5 * s.size[1];
      if (!toward.isZero(0.0) && std::abs(toward.dot(pose.R.col(2))) < kFacing * toward.norm()) break;
      for (int cap = 0; cap < 2; ++cap)
        for (int k = 0; k < kRimPoints; ++k) {
          const double angle = 2.0 * M_PI * k / kRimPoints;
          pts[n] = pose.act(Vector3(r * std::cos(angle), r * std::sin(angle), cap ? hl : -hl));
          radius[n++] = 0.0;
        }
      break;
    }
    case Kind::Capsule:
      for (int cap = 0; cap < 2; ++cap) {
        pts[n] = pose.act(Vector3(0.0, 0.0, (cap ? 0.5 : -0.5) * s.size[1]));
        radius[n++] = s.size[0];
      }
      break;
    case Kind::Sphere:
      pts[n] = pose.p;
      radius[n++] = s.size[0];
      break;
    case Kind::Mesh:
    case Kind::Plane: break;
  }
  return n;
}

// Point x of a (rounded by r) against shape b: a candidate when within reach.
void pointAgainst(const Vector3& x, double r, const CollisionShape& b, const SE3& pb, double margin, Candidates& c,
                  bool x_on_a) {
  const PointQuery q = pointQuery(b, pb, x, margin + r);
  if (!q.valid || q.distance - r >= margin) return;
  // q.normal is b's outward normal, toward x; seen from x's shape it points into it.
  const Vector3 on_x = x - r * q.normal;
  if (x_on_a) c.add(on_x, q.surface, -q.normal, q.distance - r);
  else c.add(q.surface, on_x, q.normal, q.distance - r);
}

// A sphere (centre x, radius r) against a mesh: the exact nearest surface point (point_query.h: the
// field near the surface, the mesh's hierarchy beyond its band), and where the mesh is not convex
// there (a groove, a bowl, a corner between two walls) the other places the sphere may touch: each
// triangle within reach whose nearest point to x lies in front of every contact kept so far (a
// point on or behind a kept contact's tangent plane cannot be reached before that contact is, as on
// a flat face tiled by many triangles). At most kMaxPairPoints, nearest first.
void sphereAgainstMesh(const Vector3& x, double r, const CollisionShape& mesh, const SE3& pm, double margin,
                       Candidates& c, bool x_on_a) {
  const PointQuery nearest = pointQuery(mesh, pm, x, margin + r);
  if (!nearest.valid || nearest.distance - r >= margin) return;
  auto add = [&](const Vector3& surface, const Vector3& normal, double distance) {
    // normal: the mesh's outward normal toward x; seen from x's shape it points into it.
    const Vector3 on_x = x - r * normal;
    if (x_on_a) c.add(on_x, surface, -normal, distance - r);
    else c.add(surface, on_x, normal, distance - r);
  };
  add(nearest.surface, nearest.normal, nearest.distance);
  if (!(nearest.distance > 0.0) || !mesh.triangles) return;  // the centre inside: the one way out
  constexpr int kMost = 64;         // triangles within reach considered, the nearest kept
  constexpr double kInFront = 1e-7;  // m: a point this little in front of a kept plane is on it
  struct Near {
    double distance;
    Vector3 point;
  } found[kMost];
  int n = 0;
  const TriangleMesh& tm = *mesh.triangles;
  const Vector3 xl = pm.R.transpose() * (x - pm.p);
  forEachTriangleNear(tm, xl, r + margin, [&](int t) {
    const TrianglePoint q = closestOnTriangle(tm, t, xl);
    const double d = (xl - q.point).norm();
    if (!(d - r < margin) || !(d > 1e-12)) return;
    int at = n;
    if (n < kMost) ++n;
    else if (found[--at].distance <= d) return;  // full: the farthest gives way, if this one is nearer
    for (; at > 0 && found[at - 1].distance > d; --at) found[at] = found[at - 1];
    found[at] = Near{d, q.point};
  });
  Vector3 kept_point[kMaxPairPoints], kept_normal[kMaxPairPoints];
  kept_point[0] = pm.R.transpose() * (nearest.surface - pm.p);
  kept_normal[0] = pm.R.transpose() * nearest.normal;
  int kept = 1;
  for (int i = 0; i < n && kept < kMaxPairPoints; ++i) {
    const Vector3& q = found[i].point;
    bool behind = false;
    for (int j = 0; j < kept && !behind; ++j) behind = kept_normal[j].dot(q - kept_point[j]) <= kInFront;
    if (behind) continue;
    kept_point[kept] = q;
    kept_normal[kept] = (xl - q) / found[i].distance;
    add(pm.act(q), pm.R * kept_normal[kept], found[i].distance);
    ++kept;
  }
}

// Every sample point of shape s (a mesh's samples, or its feature points) against the other shape.
void samplesAgainst(const CollisionShape& s, const SE3& ps, const CollisionShape& other, const SE3& po, double margin,
                    Candidates& c, bool s_is_a, const Vector3& toward = Vector3::Zero()) {
  if (s.kind == Kind::Mesh) {
    if (!s.samples) return;
    for (const Vector3& local : *s.samples) pointAgainst(ps.act(local), 0.0, other, po, margin, c, s_is_a);
    return;
  }
  Vector3 pts[2 * kRimPoints + 2];
  double radius[2 * kRimPoints + 2];
  const int n = featurePoints(s, ps, pts, radius, toward);
  for (int k = 0; k < n; ++k) {
    if (other.kind == Kind::Mesh && radius[k] > 0.0) sphereAgainstMesh(pts[k], radius[k], other, po, margin, c, s_is_a);
    else pointAgainst(pts[k], radius[k], other, po, margin, c, s_is_a);
  }
}

// A cylinder's rim point farthest along `toward` on each cap (exact: where a cylinder lying on its
// side touches along a line, both ends of the line), against the other shape.
void extremeRimPoints(const CollisionShape& s, const SE3& ps, const Vector3& toward, const CollisionShape& other,
                      const SE3& po, double margin, Candidates& c, bool s_is_a) {
  if (s.kind != Kind::Cylinder) return;
  const Vector3 axis = ps.R.col(2);
  const Vector3 across = toward - toward.dot(axis) * axis;
  const double len = across.norm();
  if (!(len > 1e-9)) return;  // a cap faces it: its rim points are all equally far
  for (int cap = 0; cap < 2; ++cap)
    pointAgainst(ps.p + (cap ? 0.5 : -0.5) * s.size[1] * axis + (s.size[0] / len) * across, 0.0, other, po, margin, c,
                 s_is_a);
}

// Shape b against the plane a (its frame's z = 0, solid below).
void againstPlane(const SE3& pa, const CollisionShape& b, const SE3& pb, double margin, Candidates& c) {
  const Vector3 n = pa.R.col(2);
  auto add = [&](const Vector3& x, double r) {
    const double d = n.dot(x - pa.p) - r;
    if (d >= margin) return;
    const Vector3 on_b = x - r * n;
    c.add(on_b - d * n, on_b, n, d);
  };
  if (b.kind == Kind::Mesh) {
    if (!b.samples) return;
    for (const Vector3& local : *b.samples) add(pb.act(local), 0.0);
    return;
  }
  if (b.kind == Kind::Cylinder) {
    // Each cap's lowest rim point, exactly, before the rim's fixed points (a flat cap keeps those).
    const Vector3 axis = pb.R.col(2);
    const Vector3 down = -n + n.dot(axis) * axis;  // toward the plane, across the axis
    const double len = down.norm();
    if (len > 1e-9)  // else the cap lies flat: its rim points below are all equally low
      for (int cap = 0; cap < 2; ++cap)
        add(pb.p + (cap ? 0.5 : -0.5) * b.size[1] * axis + (b.size[0] / len) * down, 0.0);
  }
  Vector3 pts[2 * kRimPoints + 2];
  double radius[2 * kRimPoints + 2];
  const int k = featurePoints(b, pb, pts, radius, n);
  for (int i = 0; i < k; ++i) add(pts[i], radius[i]);
}

// The nearest points of segments p1-q1 and p2-q2 (Ericson, Real-Time Collision Detection, 5.1.9).
void nearestOnSegments(const Vector3& p1, const Vector3& q1, const Vector3& p2, const Vector3& q2, Vector3& c1,
                       Vector3& c2) {
  const Vector3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= 1e-300 && e <= 1e-300) {
  } else if (a <= 1e-300) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double cc = d1.dot(r);
    if (e <= 1e-300) {
      s = std::clamp(-cc / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 1e-300 ? std::clamp((b * f - cc * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-cc / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - cc) / a, 0.0, 1.0);
      }
    }
  }
  c1 = p1 + d1 * s;
  c2 = p2 + d2 * t;
}

void capsules(const CollisionShape& a, const SE3& pa, const CollisionShape& b, const SE3& pb, double margin,
              Candidates& c) {
  const Vector3 ha = 0.5 * a.size[1] * pa.R.col(2), hb = 0.5 * b.size[1] * pb.R.col(2);
  Vector3 ca, cb;
  nearestOnSegments(pa.p - ha, pa.p + ha, pb.p - hb, pb.p + hb, ca, cb);
  const Vector3 gap = cb - ca;
  const double len = gap.norm();
  const Vector3 n = len > 1e-12 ? Vector3(gap / len) : Vector3(pa.R.col(0));
  const double d = len - a.size[0] - b.size[0];
  if (d < margin) c.add(ca + a.size[0] * n, cb - b.size[0] * n, n, d);
  samplesAgainst(a, pa, b, pb, margin, c, true);
  samplesAgainst(b, pb, a, pa, margin, c, false);
}

// Two boxes touching face to face, or a face over an edge: the part of one box's face (the incident
// face, the one most against the normal) that lies over the other's (the reference face, the one most
// along it), clipped to the reference face's rectangle (Sutherland-Hodgman), each corner of what is
// left with its depth below the reference face. The corners of the two boxes alone miss it where
// neither box's corner is in the contact: two boxes crossed, a box tipping over a table's edge.
void boxFaces(const CollisionShape& a, const SE3& pa, const CollisionShape& b, const SE3& pb, const Vector3& n,
              double margin, Candidates& c) {
  // The face of a box most along direction d: its axis k and side (+1 / -1).
  auto faceAlong = [](const SE3& p, const Vector3& d, int* axis, double* side, double* how) {
    *how = -1.0;
    for (int k = 0; k < 3; ++k) {
      const double dot = p.R.col(k).dot(d);
      if (std::abs(dot) > *how) {
        *how = std::abs(dot);
        *axis = k;
        *side = dot > 0.0 ? 1.0 : -1.0;
      }
    }
  };
  int ra = 0, ib = 0;
  double sa = 1.0, sb = 1.0, how_a = 0.0, how_b = 0.0;
  faceAlong(pa, n, &ra, &sa, &how_a);   // a's face toward b
  faceAlong(pb, -n, &ib, &sb, &how_b);  // b's face toward a
  // The face better aligned with the normal is the reference; the other is clipped against it. Only
  // where the normal is that face's own (snappedToFace made it so): along any other normal a depth
  // below the face is not the depth along the normal.
  if (std::max(how_a, how_b) < 1.0 - 1e-12) return;
  const bool a_refers = how_a >= how_b;
  const CollisionShape &ref = a_refers ? a : b, &inc = a_refers ? b : a;
  const SE3 &pr = a_refers ? pa : pb, &pi = a_refers ? pb : pa;
  const int rk = a_refers ? ra : ib, ik = a_refers ? ib : ra;
  const double rs = a_refers ? sa : sb, is = a_refers ? sb : sa;
  const Vector3 hr = 0.5 * ref.size, hi = 0.5 * inc.size;
  const Vector3 ref_normal = rs * pr.R.col(rk);  // outward, toward the other box
  const Vector3 ref_centre = pr.p + hr[rk] * ref_normal;
  // The incident face's corners (world), in order round it.
  const int i1 = (ik + 1) % 3, i2 = (ik + 2) % 3;
  Vector3 poly[8], next[8];
  int m = 0;
  const Vector3 face_centre = pi.p + is * hi[ik] * pi.R.col(ik);
  for (const auto& [u, v] : {std::pair{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}})
    poly[m++] = face_centre + u * hi[i1] * pi.R.col(i1) + v * hi[i2] * pi.R.col(i2);
  // Clipped by the reference face's four side planes.
  const int r1 = (rk + 1) % 3, r2 = (rk + 2) % 3;
  for (const int axis : {r1, r2})
    for (const double side : {1.0, -1.0}) {
      const Vector3 out = side * pr.R.col(axis);
      const double limit = out.dot(pr.p) + hr[axis];
      // A quadrilateral clipped by four lines keeps at most eight corners; where round-off puts a
      // corner on a line both in and out, the extra ones are duplicates (reduce drops them): not written.
      int k = 0;
      for (int e = 0; e < m; ++e) {
        const Vector3 &p = poly[e], &q = poly[(e + 1) % m];
        const double dp = out.dot(p) - limit, dq = out.dot(q) - limit;
        if (dp <= 0.0 && k < 8) next[k++] = p;
        if ((dp < 0.0) != (dq < 0.0) && dp != dq && k < 8) next[k++] = p + (q - p) * (dp / (dp - dq));
      }
      m = k;
      for (int e = 0; e < m; ++e) poly[e] = next[e];
    }
  // What is left, below the reference face by less than the margin: a contact each.
  for (int e = 0; e < m; ++e) {
    const double depth = ref_normal.dot(poly[e] - ref_centre);
    if (depth >= margin) continue;
    const Vector3 on_ref = poly[e] - depth * ref_normal;
    if (a_refers) c.add(on_ref, poly[e], n, depth);
    else c.add(poly[e], on_ref, n, depth);
  }
}

// Two boxes by their 15 separating axes (Gottschalk, Lin, Manocha 1996): the three face normals of
// each and the nine products of an edge of one with an edge of the other. Along each, the boxes
// overlap by the sum of their half-widths less the centres' distance. Where they overlap, the least
// of these is the exact depth (the Minkowski difference of two boxes has no other face normals) and
// its axis the exact normal, where EPA finds both only to its tolerance and costs a polytope. Apart,
// the largest gap along an axis is a lower bound of their distance, and it is the distance where a
// pair of points realises it. A face's axis gives the other box's face clipped to that face
// (boxFaces); an edge pair's the edges' nearest points. \return false where the axes do not settle
// it (apart, and no pair of points at the axis's gap: a corner nearest a corner): GJK measures it.
bool boxesBySeparatingAxes(const CollisionShape& a, const SE3& pa, const CollisionShape& b, const SE3& pb,
                           double margin, Candidates& c) {
  // An edge pair's axis is taken only where it beats every face's by this much: where they tie (a
  // face against a face, turned) the face's clip gives the whole contact, the edges one point of it.
  constexpr double kFaceFirst = 1e-9;  // m
  constexpr double kParallel = 1e-6;   // |edge x edge| below this: parallel edges, a face's axis already
  constexpr double kRealised = 1e-9;   // m: a pair of points this near the axis's gap realises it
  const Vector3 ha = 0.5 * a.size, hb = 0.5 * b.size;
  const Vector3 t = pb.p - pa.p;
  // The separation along unit axis u (positive: a gap).
  auto separation = [&](const Vector3& u) {
    double r = 0.0;
    for (int k = 0; k < 3; ++k) r += ha[k] * std::abs(pa.R.col(k).dot(u)) + hb[k] * std::abs(pb.R.col(k).dot(u));
    return std::abs(t.dot(u)) - r;
  };
  double best = -std::numeric_limits<double>::infinity();
  Vector3 axis = Vector3::UnitZ();
  for (int k = 0; k < 6; ++k) {
    const Vector3 u = k < 3 ? Vector3(pa.R.col(k)) : Vector3(pb.R.col(k - 3));
    const double s = separation(u);
    if (s >= margin) return true;  // apart by at least the margin: no contact
    if (s > best) {
      best = s;
      axis = u;
    }
  }
  const double best_face = best;
  int edge_i = -1, edge_j = -1;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      Vector3 u = pa.R.col(i).cross(pb.R.col(j));
      const double len = u.norm();
      if (len < kParallel) continue;
      u /= len;
      const double s = separation(u);
      if (s >= margin) return true;
      if (s > best && s > best_face + kFaceFirst) {
        best = s;
        axis = u;
        edge_i = i;
        edge_j = j;
      }
    }
  const Vector3 n = t.dot(axis) < 0.0 ? Vector3(-axis) : axis;  // from a toward b
  const int before = c.n;
  if (edge_i < 0) {
    boxFaces(a, pa, b, pb, n, margin, c);
    // Nothing of the other face over this one, or apart and no point at the axis's gap: GJK/EPA decides.
    double nearest = std::numeric_limits<double>::infinity();
    for (int k = before; k < c.n; ++k) nearest = std::min(nearest, c.p[k].distance);
    if (c.n > before && (best < 0.0 || nearest < best + kRealised)) return true;
    c.n = before;
    return false;
  }
  // The edge of a along its axis edge_i farthest toward b, and b's along edge_j farthest toward a.
  Vector3 ca = pa.p, cb = pb.p;
  for (int k = 0; k < 3; ++k) {
    if (k != edge_i) ca += (pa.R.col(k).dot(n) > 0.0 ? ha[k] : -ha[k]) * pa.R.col(k);
    if (k != edge_j) cb -= (pb.R.col(k).dot(n) > 0.0 ? hb[k] : -hb[k]) * pb.R.col(k);
  }
  const Vector3 ea = ha[edge_i] * pa.R.col(edge_i), eb = hb[edge_j] * pb.R.col(edge_j);
  Vector3 on_a, on_b;
  nearestOnSegments(ca - ea, ca + ea, cb - eb, cb + eb, on_a, on_b);
  if (best >= 0.0 && (on_b - on_a).norm() > best + kRealised) return false;  // the edges' ends apart: GJK
  c.add(on_a, on_b, n, best);
  return true;
}

// GJK/EPA's normal, or the face normal it estimates: where a box's face or a cylinder's cap lies on the
// other shape, EPA finds the face's normal only to its tolerance (1e-8 to 1e-6 off), and each step's
// error, as a tangential push on a stack that nothing else pushes sideways, tips it over in time. A face
// normal of either shape within kFaceAngle of the estimate is the contact's normal.
Vector3 snappedToFace(const CollisionShape& a, const SE3& pa, const CollisionShape& b, const SE3& pb, const Vector3& n) {
  constexpr double kFaceAngle = 1e-4;  // rad
  const double near = std::cos(kFaceAngle);
  Vector3 best = n;
  double best_dot = near;
  auto offer = [&](const CollisionShape& s, const SE3& p) {
    const int axes = s.kind == Kind::Box ? 3 : s.kind == Kind::Cylinder ? 1 : 0;
    for (int k = 0; k < axes; ++k) {
      const Vector3 u = p.R.col(s.kind == Kind::Box ? k : 2);
      const double dot = u.dot(n);
      if (std::abs(dot) > best_dot) {
        best_dot = std::abs(dot);
        best = dot > 0.0 ? u : Vector3(-u);
      }
    }
  };
  offer(a, pa);
  offer(b, pb);
  return best;
}

// Keeps at most kMaxPairPoints, spread as widely as they can be. The points within kHardlyShallower
// of the deepest come first (a face on a face: all its corners are that deep, and whichever round-off
// makes deepest must not decide which corners stay): the one farthest from their centre, the one
// farthest from it, then those that span the largest area with those; then, if room is left, the
// others by the same rule.
int reduce(const Candidates& c, ContactPoint* out) {
  constexpr double kHardlyShallower = 1e-6;  // m
  int idx[kMaxCandidates];
  int n = 0;
  for (int i = 0; i < c.n; ++i) {
    bool duplicate = false;
    for (int k = 0; k < n && !duplicate; ++k)
      duplicate = (c.p[idx[k]].point - c.p[i].point).squaredNorm() < kSamePoint * kSamePoint;
    if (!duplicate) idx[n++] = i;
  }
  if (n == 0) return 0;
  double deepest = c.p[idx[0]].distance;
  for (int k = 1; k < n; ++k) deepest = std::min(deepest, c.p[idx[k]].distance);
  // The deep ones to the front, in their order.
  int deep = 0;
  for (int k = 0; k < n; ++k)
    if (c.p[idx[k]].distance <= deepest + kHardlyShallower) std::swap(idx[deep++], idx[k]);
  for (int k = deep + 1; k < n; ++k)  // the rest by depth, stably (insertion: std::stable_sort allocates)
    for (int j = k; j > deep && c.p[idx[j]].distance < c.p[idx[j - 1]].distance; --j) std::swap(idx[j], idx[j - 1]);
  auto P = [&](int k) -> const Vector3& { return c.p[idx[k]].point; };
  const int keep = std::min(n, kMaxPairPoints);
  int chosen = 0;
  // Picks the best of [chosen, end) by score into place `chosen`.
  auto pick = [&](int end, auto score) {
    if (end - chosen == 1) {  // one left: no score to take (the last corner's three were the dearest)
      ++chosen;
      return;
    }
    int best = chosen;
    double best_score = -1.0;
    for (int k = chosen; k < end; ++k) {
      const double s = score(P(k));
      if (s > best_score) {
        best_score = s;
        best = k;
      }
    }
    std::swap(idx[chosen], idx[best]);
    ++chosen;
  };
  Vector3 centre = Vector3::Zero();
  for (int k = 0; k < deep; ++k) centre += P(k) / deep;
  auto score = [&](const Vector3& x) {
    switch (chosen) {
      case 0: return (x - centre).squaredNorm();
      case 1: return (x - P(0)).squaredNorm();
      case 2: return (P(1) - P(0)).cross(x - P(0)).squaredNorm();
      default:
        return (P(1) - P(0)).cross(x - P(0)).norm() + (P(2) - P(1)).cross(x - P(1)).norm() +
               (P(0) - P(2)).cross(x - P(2)).norm();
    }
  };
  while (chosen < keep) pick(chosen < deep ? deep : n, score);
  for (int k = 0; k < keep; ++k) out[k] = ContactPoint{c.p[idx[k]].point, c.p[idx[k]].normal, c.p[idx[k]].distance};
  // Deepest first, as the header says.
  int first = 0;
  for (int k = 1; k < keep; ++k)
    if (out[k].distance < out[first].distance) first = k;
  std::swap(out[0], out[first]);
  return keep;
}

// Two spheres: their centres' line, exactly (the crowded scene's pair: no candidates to reduce).
int spheres(const SE3& pa, double ra, const SE3& pb, double rb, double margin, ContactPoint* out) {
  const Vector3 d = pb.p - pa.p;
  const double len2 = d.squaredNorm(), reach = ra + rb + margin;
  if (!(len2 < reach * reach)) return 0;
  const double len = std::sqrt(len2);
  // Concentric: b's own z, as the point query against b gives it.
  const Vector3 n = len > 1e-15 ? Vector3(d / len) : Vector3(-pb.R.col(2));
  out[0] = ContactPoint{0.5 * ((pa.p + ra * n) + (pb.p - rb * n)), n, len - ra - rb};
  return 1;
}

}  // namespace

int shapeContacts(const CollisionShape& a, const SE3& pa, const CollisionShape& b, const SE3& pb, double margin,
                  ContactPoint* out) {
  if (a.kind == Kind::Sphere && b.kind == Kind::Sphere) return spheres(pa, a.size[0], pb, b.size[0], margin, out);
  if (b.kind == Kind::Plane && a.kind != Kind::Plane) {
    const int n = shapeContacts(b, pb, a, pa, margin, out);
    for (int k = 0; k < n; ++k) out[k].normal = -out[k].normal;
    return n;
  }
  Candidates c;
  if (a.kind == Kind::Plane) {
    if (b.kind == Kind::Plane) return 0;
    againstPlane(pa, b, pb, margin, c);
  } else if (a.kind == Kind::Sphere) {
    if (b.kind == Kind::Mesh) sphereAgainstMesh(pa.p, a.size[0], b, pb, margin, c, true);
    else pointAgainst(pa.p, a.size[0], b, pb, margin, c, true);
  } else if (b.kind == Kind::Sphere) {
    if (a.kind == Kind::Mesh) sphereAgainstMesh(pb.p, b.size[0], a, pa, margin, c, false);
    else pointAgainst(pb.p, b.size[0], a, pa, margin, c, false);
  } else if (a.kind == Kind::Mesh || b.kind == Kind::Mesh) {
    samplesAgainst(a, pa, b, pb, margin, c, true);
    samplesAgainst(b, pb, a, pa, margin, c, false);
    // A cylinder's side on a mesh: each cap's rim point farthest toward the mesh (its nearest surface
    // from the cylinder's centre), exactly, where the rim's fixed points would leave it sunk between them.
    for (const bool cyl_is_a : {true, false}) {
      const CollisionShape &cyl = cyl_is_a ? a : b, &mesh = cyl_is_a ? b : a;
      const SE3 &pc = cyl_is_a ? pa : pb, &pm = cyl_is_a ? pb : pa;
      if (cyl.kind != Kind::Cylinder || mesh.kind != Kind::Mesh) continue;
      const PointQuery q = pointQuery(mesh, pm, pc.p, margin + std::hypot(cyl.size[0], 0.5 * cyl.size[1]));
      if (q.valid) extremeRimPoints(cyl, pc, -q.normal, mesh, pm, margin, c, cyl_is_a);
    }
  } else if (a.kind == Kind::Capsule && b.kind == Kind::Capsule) {
    capsules(a, pa, b, pb, margin, c);
  } else if (a.kind == Kind::Box && b.kind == Kind::Box && boxesBySeparatingAxes(a, pa, b, pb, margin, c)) {
    // their points are in c
  } else {
    ConvexShape ca, cb;
    convexOf(a, pa, &ca);
    convexOf(b, pb, &cb);
    ConvexDistance d = convexDistance(ca, cb);
    if (!d.ok || d.distance >= margin) return 0;
    d.normal = snappedToFace(a, pa, b, pb, d.normal);
    c.add(d.on_a, d.on_b, d.normal, d.distance);
    // Corners, rims and ends against the other shape (their exact gaps) share the pair's normal: a
    // corner on another's edge has no normal of its own (a stacked box's corners sit on the edges of
    // the box below), and one contact has one normal.
    const int first = c.n;
    samplesAgainst(a, pa, b, pb, margin, c, true, d.normal);
    samplesAgainst(b, pb, a, pa, margin, c, false, d.normal);
    // d.normal points from a toward b: a's rim points farthest that way, b's farthest back.
    extremeRimPoints(a, pa, d.normal, b, pb, margin, c, true);
    extremeRimPoints(b, pb, -d.normal, a, pa, margin, c, false);
    if (a.kind == Kind::Box && b.kind == Kind::Box) boxFaces(a, pa, b, pb, d.normal, margin, c);
    for (int k = first; k < c.n; ++k) c.p[k].normal = d.normal;
  }
  return reduce(c, out);
}

}  // namespace igms
