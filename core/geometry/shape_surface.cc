#include "core/geometry/shape_surface.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace igms {

namespace {

struct ProfilePoint {
  double radius, z;
};

// A solid of revolution about z: `profile` runs from the bottom pole to the top pole (radius 0 at both
// ends), each inner point becomes a ring of `segments` vertices. Triangles wind outward.
TriangleMesh lathe(const std::vector<ProfilePoint>& profile, int segments) {
  TriangleMesh m;
  const int rings = static_cast<int>(profile.size()) - 2;
  m.vertices.emplace_back(0.0, 0.0, profile.front().z);
  for (int i = 1; i <= rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double a = 2.0 * M_PI * j / segments;
      m.vertices.emplace_back(profile[i].radius * std::cos(a), profile[i].radius * std::sin(a), profile[i].z);
    }
  const int top = static_cast<int>(m.vertices.size());
  m.vertices.emplace_back(0.0, 0.0, profile.back().z);
  auto ring = [&](int i, int j) { return 1 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) {
    m.triangles.push_back({0, ring(1, j + 1), ring(1, j)});
    for (int i = 1; i < rings; ++i) {
      m.triangles.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
      m.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
    }
    m.triangles.push_back({top, ring(rings, j), ring(rings, j + 1)});
  }
  return m;
}

// An arc of radius r about z = centre, from angle `from` to `to` (radians from the equator),
// `steps` intervals, the first point included and the last not.
void arc(std::vector<ProfilePoint>& out, double r, double centre, double from, double to, int steps) {
  for (int k = 0; k < steps; ++k) {
    const double a = from + (to - from) * k / steps;
    out.push_back({r * std::cos(a), centre + r * std::sin(a)});
  }
}

TriangleMesh box(const Vector3& size) {
  TriangleMesh m;
  const Vector3 h = 0.5 * size;
  for (int k = 0; k < 8; ++k) m.vertices.emplace_back(k & 1 ? h.x() : -h.x(), k & 2 ? h.y() : -h.y(), k & 4 ? h.z() : -h.z());
  // Two triangles a face, counter-clockwise seen from outside.
  const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : faces) {
    m.triangles.push_back({f[0], f[1], f[2]});
    m.triangles.push_back({f[0], f[2], f[3]});
  }
  return m;
}

}  // namespace

TriangleMesh shapeSurface(const CollisionShape& s, int segments) {
  const int half_turn = std::max(2, segments / 2);  // rings from pole to pole
  switch (s.kind) {
    case CollisionShape::Kind::Box: return box(s.size);
    case CollisionShape::Kind::Sphere: {
      std::vector<ProfilePoint> p;
      arc(p, s.size[0], 0.0, -M_PI / 2, M_PI / 2, half_turn);
      p.push_back({0.0, s.size[0]});
      return lathe(p, segments);
    }
    case CollisionShape::Kind::Cylinder: {
      const double r = s.size[0], h = 0.5 * s.size[1];
      return lathe({{0.0, -h}, {r, -h}, {r, h}, {0.0, h}}, segments);
    }
    case CollisionShape::Kind::Capsule: {
      const double r = s.size[0], h = 0.5 * s.size[1];
      std::vector<ProfilePoint> p;
      arc(p, r, -h, -M_PI / 2, 0.0, std::max(1, half_turn / 2));
      p.push_back({r, -h});
      arc(p, r, h, 0.0, M_PI / 2, std::max(1, half_turn / 2));
      p.push_back({0.0, h + r});
      return lathe(p, segments);
    }
    case CollisionShape::Kind::Mesh: {
      TriangleMesh m;
      if (s.triangles) {
        m.vertices = s.triangles->vertices;
        m.triangles = s.triangles->triangles;
      }
      return m;
    }
    case CollisionShape::Kind::Plane: return {};
  }
  return {};
}

}  // namespace igms
