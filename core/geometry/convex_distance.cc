#include "core/geometry/convex_distance.h"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>

namespace igms {
namespace {

constexpr int kGjkIterations = 64;
constexpr int kEpaVertices = 96;
constexpr int kEpaFaces = 2 * kEpaVertices;
constexpr double kRelativeTolerance = 1e-12;  // GJK: the lower bound meets the upper within this (squared)
constexpr double kAbsoluteGap = 1e-13;        // m: or within this
constexpr double kEpaTolerance = 1e-10;       // m: EPA stops when a face's support adds less

double sign(double x) { return x < 0.0 ? -1.0 : 1.0; }  // 0 -> +1: deterministic

// A point of the Minkowski difference a - b and the two support points behind it.
struct Vertex {
  Vector3 w, a, b;
};

Vertex supportVertex(const ConvexShape& A, const ConvexShape& B, const Vector3& d) {
  Vertex v;
  v.a = supportPoint(A, d);
  v.b = supportPoint(B, -d);
  v.w = v.a - v.b;
  return v;
}

// The simplex of GJK: up to four vertices with the barycentric weights of its point nearest the origin.
struct Simplex {
  Vertex v[4];
  double lambda[4] = {1, 0, 0, 0};
  int n = 0;
  Vector3 point() const {
    Vector3 x = Vector3::Zero();
    for (int i = 0; i < n; ++i) x += lambda[i] * v[i].w;
    return x;
  }
  void keep(std::initializer_list<int> which, std::initializer_list<double> weights) {
    Vertex kept[4];
    double l[4];
    int k = 0;
    auto w = weights.begin();
    for (int i : which) {
      kept[k] = v[i];
      l[k++] = *w++;
    }
    for (int i = 0; i < k; ++i) {
      v[i] = kept[i];
      lambda[i] = l[i];
    }
    n = k;
  }
};

// Reduces a segment, triangle or tetrahedron to the face nearest the origin (Ericson, Real-Time
// Collision Detection, 5.1.2 and 5.1.5). \return true when the tetrahedron contains the origin.
void nearestOnSegment(Simplex& s, int i, int j) {
  const Vector3& a = s.v[i].w;
  const Vector3 ab = s.v[j].w - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp(-a.dot(ab) / len2, 0.0, 1.0) : 0.0;
  if (t <= 0.0) s.keep({i}, {1.0});
  else if (t >= 1.0) s.keep({j}, {1.0});
  else s.keep({i, j}, {1.0 - t, t});
}

void nearestOnTriangle(Simplex& s, int ia, int ib, int ic) {
  const Vector3 &a = s.v[ia].w, &b = s.v[ib].w, &c = s.v[ic].w;
  const Vector3 ab = b - a, ac = c - a, ap = -a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return s.keep({ia}, {1.0});
  const Vector3 bp = -b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return s.keep({ib}, {1.0});
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return s.keep({ia, ib}, {1.0 - v, v});
  }
  const Vector3 cp = -c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return s.keep({ic}, {1.0});
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return s.keep({ia, ic}, {1.0 - w, w});
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return s.keep({ib, ic}, {1.0 - w, w});
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0.0)) return nearestOnSegment(s, ia, ib);  // a degenerate triangle
  const double v = vb / denom, w = vc / denom;
  s.keep({ia, ib, ic}, {1.0 - v - w, v, w});
}

// Is the origin on the far side of face (a, b, c) from d?
bool originOutside(const Vector3& a, const Vector3& b, const Vector3& c, const Vector3& d) {
  const Vector3 n = (b - a).cross(c - a);
  const double side_origin = -a.dot(n), side_d = (d - a).dot(n);
  return side_origin * side_d < 0.0;
}

bool nearestOnTetrahedron(Simplex& s) {
  static constexpr int kFaces[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
  double best = std::numeric_limits<double>::infinity();
  Simplex nearest;
  bool outside_any = false;
  // A flat tetrahedron (the new point on the plane of the others: a box's face) contains nothing:
  // its nearest face answers.
  const Vector3 e1 = s.v[1].w - s.v[0].w, e2 = s.v[2].w - s.v[0].w, e3 = s.v[3].w - s.v[0].w;
  const double scale = std::max({e1.norm(), e2.norm(), e3.norm()});
  const bool flat = std::abs(e1.dot(e2.cross(e3))) <= 1e-12 * scale * scale * scale;
  for (const auto& f : kFaces) {
    if (!flat && !originOutside(s.v[f[0]].w, s.v[f[1]].w, s.v[f[2]].w, s.v[f[3]].w)) continue;
    outside_any = true;
    Simplex t = s;
    nearestOnTriangle(t, f[0], f[1], f[2]);
    const double d = t.point().squaredNorm();
    if (d < best) {
      best = d;
      nearest = t;
    }
  }
  if (!outside_any) return true;
  s = nearest;
  return false;
}

// EPA's polytope: triangles of the Minkowski difference around the origin, outward normals, each
// knowing its three neighbours (edge e of a face runs from v[e] to v[e + 1]; adj[e] is the face
// across it, which has the same edge as its adj_edge[e]). Faces are never moved: their indices stay.
struct Polytope {
  Vertex v[kEpaVertices];
  int nv = 0;
  struct Face {
    int v[3];
    int adj[3];
    int adj_edge[3];
    Vector3 n;
    double d;
    bool live;
  } f[kEpaFaces];
  int nf = 0;

  // A new face (a, b, c); false when full or when it has no direction (a sliver).
  int addFace(int a, int b, int c) {
    if (nf >= kEpaFaces) return -1;
    Vector3 n = (v[b].w - v[a].w).cross(v[c].w - v[a].w);
    const double len = n.norm();
    if (!(len > 1e-300)) return -1;
    n /= len;
    Face& F = f[nf];
    F.v[0] = a;
    F.v[1] = b;
    F.v[2] = c;
    F.n = n;
    F.d = n.dot(v[a].w);
    F.live = true;
    return nf++;
  }
  void link(int fa, int ea, int fb, int eb) {
    f[fa].adj[ea] = fb;
    f[fa].adj_edge[ea] = eb;
    f[fb].adj[eb] = fa;
    f[fb].adj_edge[eb] = ea;
  }
};

// The faces a new point sees, from the one it was found for across their neighbours (so the hole
// stays one disc); the edges round the hole, each as (face outside it, its edge).
struct Horizon {
  int face[kEpaFaces];
  int edge[kEpaFaces];
  int n = 0;
};

void carve(Polytope& p, int face, int edge, const Vector3& w, Horizon& h) {
  // An explicit stack: (face, the edge we came in through).
  int stack_face[kEpaFaces * 3], stack_edge[kEpaFaces * 3];
  int top = 0;
  stack_face[top] = face;
  stack_edge[top++] = edge;
  while (top > 0) {
    const int g = stack_face[--top], e = stack_edge[top];
    Polytope::Face& F = p.f[g];
    if (!F.live) continue;
    if (F.n.dot(w - p.v[F.v[0]].w) <= 0.0) {  // not seen: its edge e borders the hole
      if (h.n < kEpaFaces) {
        h.face[h.n] = g;
        h.edge[h.n++] = e;
      }
      continue;
    }
    F.live = false;
    // Its other two edges, pushed so that the next edge after e is visited first.
    for (int k = 2; k >= 1; --k) {
      const int ek = (e + k) % 3;
      stack_face[top] = F.adj[ek];
      stack_edge[top++] = F.adj_edge[ek];
    }
  }
}

// Grows a simplex that touches the origin into a tetrahedron around it (the cores touch or overlap).
bool tetrahedronAroundOrigin(const ConvexShape& A, const ConvexShape& B, Simplex& s) {
  static const Vector3 kAxes[6] = {Vector3::UnitX(), -Vector3::UnitX(), Vector3::UnitY(),
                                   -Vector3::UnitY(), Vector3::UnitZ(), -Vector3::UnitZ()};
  if (s.n == 1) {
    for (const Vector3& d : kAxes) {
      const Vertex w = supportVertex(A, B, d);
      if ((w.w - s.v[0].w).squaredNorm() > 1e-24) {
        s.v[s.n++] = w;
        break;
      }
    }
    if (s.n < 2) return false;
  }
  if (s.n == 2) {
    const Vector3 line = s.v[1].w - s.v[0].w;
    int k = 0;
    for (int a = 1; a < 3; ++a)
      if (std::abs(line[a]) < std::abs(line[k])) k = a;
    const Vector3 perp = line.cross(Vector3::Unit(k)).normalized();
    for (int t = 0; t < 6 && s.n < 3; ++t) {
      const double angle = t * M_PI / 3.0;
      const Vector3 d = Eigen::AngleAxisd(angle, line.normalized()) * perp;
      const Vertex w = supportVertex(A, B, d);
      if ((w.w - s.v[0].w).cross(line).squaredNorm() > 1e-24 * line.squaredNorm()) s.v[s.n++] = w;
    }
    if (s.n < 3) return false;
  }
  if (s.n == 3) {
    const Vector3 n = (s.v[1].w - s.v[0].w).cross(s.v[2].w - s.v[0].w);
    for (const Vector3& d : {n, Vector3(-n)}) {
      const Vertex w = supportVertex(A, B, d);
      if (std::abs((w.w - s.v[0].w).dot(n)) > 1e-12 * n.norm()) {
        s.v[s.n++] = w;
        break;
      }
    }
    if (s.n < 4) return false;
  }
  return true;
}

ConvexDistance epa(const ConvexShape& A, const ConvexShape& B, Simplex& s) {
  ConvexDistance out;
  if (!tetrahedronAroundOrigin(A, B, s)) return out;
  Polytope p;
  for (int i = 0; i < 4; ++i) p.v[p.nv++] = s.v[i];
  // Orient the tetrahedron so that (0, 1, 2) faces away from vertex 3.
  if ((p.v[1].w - p.v[0].w).cross(p.v[2].w - p.v[0].w).dot(p.v[3].w - p.v[0].w) > 0.0) std::swap(p.v[1], p.v[2]);
  static constexpr int kFaces[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
  for (const auto& t : kFaces)
    if (p.addFace(t[0], t[1], t[2]) < 0) return out;
  // Neighbours: the face sharing each edge reversed.
  for (int a = 0; a < 4; ++a)
    for (int ea = 0; ea < 3; ++ea)
      for (int b = 0; b < 4; ++b)
        for (int eb = 0; eb < 3; ++eb)
          if (p.f[a].v[ea] == p.f[b].v[(eb + 1) % 3] && p.f[a].v[(ea + 1) % 3] == p.f[b].v[eb]) {
            p.f[a].adj[ea] = b;
            p.f[a].adj_edge[ea] = eb;
          }
  auto nearestFace = [&] {
    int best = -1;
    for (int k = 0; k < p.nf; ++k)
      if (p.f[k].live && (best < 0 || p.f[k].d < p.f[best].d)) best = k;
    return best;
  };
  int best = nearestFace();
  while (best >= 0 && p.nv < kEpaVertices) {
    const Polytope::Face face = p.f[best];
    const Vertex w = supportVertex(A, B, face.n);
    if (face.n.dot(w.w) - face.d < kEpaTolerance) break;
    // Carve the faces w sees, starting from this one, and close the hole with a fan to w.
    Horizon h;
    p.f[best].live = false;
    for (int e = 0; e < 3; ++e) carve(p, face.adj[e], face.adj_edge[e], w.w, h);
    if (h.n < 3 || p.nf + h.n > kEpaFaces) break;
    const int iw = p.nv;
    p.v[p.nv++] = w;
    const int first = p.nf;
    bool ok = true;
    for (int k = 0; k < h.n && ok; ++k) {
      const Polytope::Face& g = p.f[h.face[k]];
      const int a = g.v[h.edge[k]], b = g.v[(h.edge[k] + 1) % 3];
      const int nf = p.addFace(b, a, iw);  // edge 0 (b -> a) is g's edge reversed
      ok = nf >= 0;
      if (ok) p.link(nf, 0, h.face[k], h.edge[k]);
    }
    if (!ok) break;  // a sliver: stop with what the polytope had (it is still closed but for the fan)
    // Edge 1 (a -> w) of one new face borders edge 2 (w -> b') of the one whose b' is this a.
    for (int k = first; k < p.nf; ++k)
      for (int j = first; j < p.nf; ++j)
        if (p.f[j].v[0] == p.f[k].v[1]) p.link(k, 1, j, 2);
    best = nearestFace();
  }
  best = nearestFace();
  if (best < 0) return out;
  const Polytope::Face& face = p.f[best];
  // The origin's projection on the face, in barycentric weights of its three vertices.
  const Vector3 x = face.d * face.n;
  const Vector3 &a = p.v[face.v[0]].w, &b = p.v[face.v[1]].w, &c = p.v[face.v[2]].w;
  const Vector3 v0 = b - a, v1 = c - a, v2 = x - a;
  const double d00 = v0.dot(v0), d01 = v0.dot(v1), d11 = v1.dot(v1), d20 = v2.dot(v0), d21 = v2.dot(v1);
  const double denom = d00 * d11 - d01 * d01;
  double wb = 1.0 / 3.0, wc = 1.0 / 3.0;
  if (std::abs(denom) > 1e-300) {
    wb = (d11 * d20 - d01 * d21) / denom;
    wc = (d00 * d21 - d01 * d20) / denom;
  }
  const double wa = 1.0 - wb - wc;
  out.ok = true;
  out.normal = face.n;
  out.on_a = wa * p.v[face.v[0]].a + wb * p.v[face.v[1]].a + wc * p.v[face.v[2]].a;
  out.on_b = wa * p.v[face.v[0]].b + wb * p.v[face.v[1]].b + wc * p.v[face.v[2]].b;
  // The overlap along the face's normal, from the supports: never less than the true depth (the
  // face's own distance is, where the polytope stopped short of a curved core).
  // The witness points keep their midpoint and move apart (or together) along the normal to match.
  const Vertex w = supportVertex(A, B, face.n);
  const double depth = std::max(face.d, face.n.dot(w.w));
  const Vector3 mid = 0.5 * (out.on_a + out.on_b);
  out.on_a = mid + 0.5 * depth * face.n;
  out.on_b = mid - 0.5 * depth * face.n;
  out.distance = -depth;
  return out;
}

}  // namespace

bool convexOf(const CollisionShape& shape, const SE3& pose, ConvexShape* out) {
  out->pose = pose;
  out->radius = 0.0;
  switch (shape.kind) {
    case CollisionShape::Kind::Sphere:
      out->core = ConvexShape::Core::Point;
      out->half.setZero();
      out->radius = shape.size[0];
      return true;
    case CollisionShape::Kind::Capsule:
      out->core = ConvexShape::Core::Segment;
      out->half = Vector3(0.0, 0.0, 0.5 * shape.size[1]);
      out->radius = shape.size[0];
      return true;
    case CollisionShape::Kind::Box:
      out->core = ConvexShape::Core::Box;
      out->half = 0.5 * shape.size;
      return true;
    case CollisionShape::Kind::Cylinder:
      out->core = ConvexShape::Core::Cylinder;
      out->half = Vector3(shape.size[0], 0.0, 0.5 * shape.size[1]);
      return true;
    case CollisionShape::Kind::Mesh:
    case CollisionShape::Kind::Plane: return false;
  }
  return false;
}

Vector3 supportPoint(const ConvexShape& s, const Vector3& d_world) {
  const Vector3 d = s.pose.R.transpose() * d_world;
  Vector3 local = Vector3::Zero();
  switch (s.core) {
    case ConvexShape::Core::Point: break;
    case ConvexShape::Core::Segment: local.z() = sign(d.z()) * s.half.z(); break;
    case ConvexShape::Core::Box:
      local = Vector3(sign(d.x()) * s.half.x(), sign(d.y()) * s.half.y(), sign(d.z()) * s.half.z());
      break;
    case ConvexShape::Core::Cylinder: {
      const double rho = std::hypot(d.x(), d.y());
      if (rho > 1e-300) local.head<2>() = (s.half.x() / rho) * d.head<2>();
      local.z() = sign(d.z()) * s.half.z();
      break;
    }
  }
  return s.pose.act(local);
}

namespace {

// GJK and EPA on the cores as given.
ConvexDistance coreDistance(const ConvexShape& A, const ConvexShape& B) {
  Simplex s;
  Vector3 d = B.pose.p - A.pose.p;  // first guess: along the centres
  if (d.squaredNorm() < 1e-24) d = Vector3::UnitX();
  s.v[0] = supportVertex(A, B, -d);
  s.n = 1;
  ConvexDistance out;
  bool overlap = false;
  for (int iter = 0; iter < kGjkIterations; ++iter) {
    if (s.n == 2) nearestOnSegment(s, 0, 1);
    else if (s.n == 3) nearestOnTriangle(s, 0, 1, 2);
    else if (s.n == 4 && nearestOnTetrahedron(s)) {
      overlap = true;
      break;
    }
    const Vector3 x = s.point();
    const double x2 = x.squaredNorm();
    if (x2 < 1e-24) {
      overlap = true;
      break;
    }
    const Vertex w = supportVertex(A, B, -x);
    // The distance lies between x.w/|x| and |x|: stop when they meet.
    bool repeated = false;
    for (int i = 0; i < s.n; ++i) repeated |= (s.v[i].w - w.w).squaredNorm() < 1e-24;
    if (repeated || x2 - x.dot(w.w) <= kRelativeTolerance * x2 + kAbsoluteGap * std::sqrt(x2)) break;
    s.v[s.n] = w;
    s.lambda[s.n] = 0.0;
    ++s.n;
  }
  if (overlap) return epa(A, B, s);
  Vector3 pa = Vector3::Zero(), pb = Vector3::Zero();
  for (int i = 0; i < s.n; ++i) {
    pa += s.lambda[i] * s.v[i].a;
    pb += s.lambda[i] * s.v[i].b;
  }
  const Vector3 gap = pb - pa;
  const double len = gap.norm();
  out.ok = len > 0.0;
  if (!out.ok) return out;
  out.normal = gap / len;
  out.on_a = pa;
  out.on_b = pb;
  out.distance = len;
  return out;
}

// A box or cylinder core shrunk by `by` and rounded by as much: the same shape but for its edges'
// rounding (by at most 0.73 `by`). Two faces that touch (a box resting on a box) then leave their
// cores apart, which GJK answers cleanly; EPA is left for real overlaps, where the origin lies well
// inside the difference of the cores (touching, it lies on its boundary, EPA's degenerate case).
ConvexShape shrunk(const ConvexShape& s, double by) {
  ConvexShape out = s;
  if (s.core == ConvexShape::Core::Box) out.half -= Vector3::Constant(by);
  else if (s.core == ConvexShape::Core::Cylinder) out.half -= Vector3(by, 0.0, by);
  else return out;
  out.radius += by;
  return out;
}

double shrinkOf(const ConvexShape& s) {
  constexpr double kRounding = 1e-7;  // m
  switch (s.core) {
    case ConvexShape::Core::Box: return std::min(kRounding, 0.01 * s.half.minCoeff());
    case ConvexShape::Core::Cylinder: return std::min(kRounding, 0.01 * std::min(s.half.x(), s.half.z()));
    default: return 0.0;
  }
}

}  // namespace

ConvexDistance convexDistance(const ConvexShape& A0, const ConvexShape& B0) {
  const ConvexShape A = shrunk(A0, shrinkOf(A0)), B = shrunk(B0, shrinkOf(B0));
  ConvexDistance out = coreDistance(A, B);
  if (!out.ok) return out;
  out.on_a += A.radius * out.normal;
  out.on_b -= B.radius * out.normal;
  out.distance -= A.radius + B.radius;
  return out;
}

}  // namespace igms
