#include "core/geometry/point_query.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/geometry/mesh_query.h"
#include "core/model/closest_point_on_triangle.h"

namespace igms {
namespace {

// The signed distance at p and its gradient (the outward normal) from the
// trilinear interpolation of the field's grid. False when p is outside the
// grid or farther than `reach` from the surface: nothing to touch. The
// gradient is zero on a flat spot (deep inside, where the field is clamped).
bool sampleField(const DistanceField& f, const Vector3& p, double reach, double* distance, Vector3* gradient) {
  const Vector3 g = (p - f.origin) / f.spacing;
  const int i = static_cast<int>(std::floor(g.x())), j = static_cast<int>(std::floor(g.y())),
            k = static_cast<int>(std::floor(g.z()));
  if (i < 0 || j < 0 || k < 0 || i >= f.nx - 1 || j >= f.ny - 1 || k >= f.nz - 1) return false;
  const double u = g.x() - i, v = g.y() - j, w = g.z() - k;
  const double c000 = f.at(i, j, k), c100 = f.at(i + 1, j, k), c010 = f.at(i, j + 1, k), c110 = f.at(i + 1, j + 1, k);
  const double c001 = f.at(i, j, k + 1), c101 = f.at(i + 1, j, k + 1), c011 = f.at(i, j + 1, k + 1),
               c111 = f.at(i + 1, j + 1, k + 1);
  const double c00 = c000 + u * (c100 - c000), c10 = c010 + u * (c110 - c010);
  const double c01 = c001 + u * (c101 - c001), c11 = c011 + u * (c111 - c011);
  const double c0 = c00 + v * (c10 - c00), c1 = c01 + v * (c11 - c01);
  *distance = c0 + w * (c1 - c0);
  if (*distance >= reach) return false;
  // The analytic gradient of the trilinear interpolant.
  const double dx = (1 - w) * ((1 - v) * (c100 - c000) + v * (c110 - c010)) + w * ((1 - v) * (c101 - c001) + v * (c111 - c011));
  const double dy = (1 - w) * (c10 - c00) + w * (c11 - c01);
  const double dz = c1 - c0;
  *gradient = Vector3(dx, dy, dz) / f.spacing;
  return true;
}

// Near the surface, the exact distance: to the nearest of the triangles the
// grid stored for the 27 grid points around p (p's nearest triangle is one of
// them but where features are thinner than the grid; mesh_contact_test
// measures it against FCL). The normal is the exact gradient of the distance,
// p's offset from its nearest point (the face's normal on the surface itself);
// the side is the face's where that point lies inside a face, else the
// interpolated field's. False when none of those points lies within the band.
constexpr int kSide = 3, kNeighbourhood = kSide * kSide * kSide;  // grid points around the nearest one

bool nearestOnMesh(const DistanceField& f, const TriangleMesh& mesh, const Vector3& p, double field_distance,
                   double* distance, Vector3* normal, Vector3* surface) {
  const Vector3 g = (p - f.origin) / f.spacing;
  const int i = static_cast<int>(std::lround(g.x())), j = static_cast<int>(std::lround(g.y())),
            k = static_cast<int>(std::lround(g.z()));
  int32_t seen[kNeighbourhood];
  int n_seen = 0;
  double best = 1e300;
  TrianglePoint at;
  int32_t best_triangle = -1;
  for (int corner = 0; corner < kNeighbourhood; ++corner) {
    const int ci = std::clamp(i - 1 + corner % kSide, 0, f.nx - 1);
    const int cj = std::clamp(j - 1 + (corner / kSide) % kSide, 0, f.ny - 1);
    const int ck = std::clamp(k - 1 + corner / (kSide * kSide), 0, f.nz - 1);
    const int32_t t = f.nearest[f.index(ci, cj, ck)];
    if (t < 0 || std::find(seen, seen + n_seen, t) != seen + n_seen) continue;
    seen[n_seen++] = t;
    const auto& tri = mesh.triangles[static_cast<size_t>(t)];
    const TrianglePoint q = closestPointOnTriangle(p, mesh.vertices[static_cast<size_t>(tri[0])],
                                                   mesh.vertices[static_cast<size_t>(tri[1])],
                                                   mesh.vertices[static_cast<size_t>(tri[2])]);
    const double d = (p - q.point).squaredNorm();
    if (d < best) {
      best = d;
      at = q;
      best_triangle = t;
    }
  }
  if (best_triangle < 0) return false;
  const auto& tri = mesh.triangles[static_cast<size_t>(best_triangle)];
  const Vector3& a = mesh.vertices[static_cast<size_t>(tri[0])];
  const Vector3 face = (mesh.vertices[static_cast<size_t>(tri[1])] - a).cross(mesh.vertices[static_cast<size_t>(tri[2])] - a);
  const Vector3 offset = p - at.point;
  const double unsigned_distance = std::sqrt(best);
  const bool inside = at.in_face ? offset.dot(face) < 0.0 : field_distance < 0.0;
  *distance = inside ? -unsigned_distance : unsigned_distance;
  const double face_norm = face.norm();
  if (unsigned_distance > 1e-9) *normal = (inside ? -offset : offset) / unsigned_distance;
  else if (face_norm > 0.0) *normal = face / face_norm;
  else return false;
  *surface = at.point;
  return true;
}

// Closest surface point and outward normal of a shape, in its own frame, for a
// point c; inside = c is inside the shape.
void closestOnBox(const Vector3& half, const Vector3& c, Vector3& surface, Vector3& normal, bool& inside) {
  const Vector3 clamped = c.cwiseMax(-half).cwiseMin(half);
  inside = clamped == c;
  if (!inside) {
    surface = clamped;
    normal = (c - clamped).normalized();
    return;
  }
  // Inside: leave through the nearest face.
  int axis = 0;
  double best = 1e300;
  for (int k = 0; k < 3; ++k) {
    const double d = half[k] - std::abs(c[k]);
    if (d < best) { best = d; axis = k; }
  }
  surface = c;
  const double sign = c[axis] >= 0.0 ? 1.0 : -1.0;
  surface[axis] = sign * half[axis];
  normal = Vector3::Zero();
  normal[axis] = sign;
}

void closestOnCylinder(double radius, double half_length, const Vector3& c, Vector3& surface, Vector3& normal,
                       bool& inside) {
  const double rho = std::hypot(c.x(), c.y());
  const Vector3 radial = rho > 1e-15 ? Vector3(c.x() / rho, c.y() / rho, 0.0) : Vector3::UnitX();
  const double z = c.z();
  inside = rho <= radius && std::abs(z) <= half_length;
  if (!inside) {
    const double zc = std::clamp(z, -half_length, half_length);
    const double rc = std::min(rho, radius);
    surface = Vector3(radial.x() * rc, radial.y() * rc, zc);
    normal = (c - surface).normalized();
    return;
  }
  const double to_side = radius - rho, to_cap = half_length - std::abs(z);
  if (to_side < to_cap) {
    surface = Vector3(radial.x() * radius, radial.y() * radius, z);
    normal = radial;
  } else {
    const double sign = z >= 0.0 ? 1.0 : -1.0;
    surface = Vector3(c.x(), c.y(), sign * half_length);
    normal = Vector3(0, 0, sign);
  }
}

// A sphere of radius r about `centre` (the sphere, and the capsule about its nearest axis point).
void closestOnSphere(const Vector3& centre, double r, const Vector3& c, Vector3& surface, Vector3& normal, bool& inside) {
  const Vector3 d = c - centre;
  const double len = d.norm();
  normal = len > 1e-15 ? Vector3(d / len) : Vector3::UnitZ();
  surface = centre + normal * r;
  inside = len < r;
}

}  // namespace

double fieldSignedDistance(const CollisionShape& mesh, const SE3& pose, const Vector3& p) {
  double distance = 0.0;
  Vector3 gradient;
  if (!mesh.field ||
      !sampleField(*mesh.field, pose.R.transpose() * (p - pose.p), std::numeric_limits<double>::infinity(), &distance,
                   &gradient))
    return std::numeric_limits<double>::infinity();
  return distance;
}

PointQuery pointQuery(const CollisionShape& shape, const SE3& pose, const Vector3& p, double reach) {
  PointQuery out;
  const Vector3 c = pose.R.transpose() * (p - pose.p);  // p in the shape frame
  Vector3 surface = Vector3::Zero(), normal = Vector3::UnitZ();
  bool inside = false;
  switch (shape.kind) {
    case CollisionShape::Kind::Box:
      closestOnBox(0.5 * shape.size, c, surface, normal, inside);
      break;
    case CollisionShape::Kind::Cylinder:
      closestOnCylinder(shape.size[0], 0.5 * shape.size[1], c, surface, normal, inside);
      break;
    case CollisionShape::Kind::Sphere: {
      const double r = c.norm();
      normal = r > 1e-15 ? Vector3(c / r) : Vector3::UnitZ();
      surface = normal * shape.size[0];
      inside = r < shape.size[0];
      break;
    }
    case CollisionShape::Kind::Capsule: {
      const double half = 0.5 * shape.size[1];
      closestOnSphere(Vector3(0.0, 0.0, std::clamp(c.z(), -half, half)), shape.size[0], c, surface, normal, inside);
      break;
    }
    case CollisionShape::Kind::Plane:
      out.valid = true;
      out.distance = c.z();
      out.normal = pose.R.col(2);
      out.surface = pose.act(Vector3(c.x(), c.y(), 0.0));
      return out;
    case CollisionShape::Kind::Mesh: {
      if (!shape.field) return out;  // no field: a mesh from a description read as text
      const DistanceField& f = *shape.field;
      double distance = 0.0;
      Vector3 gradient;
      // Each corner's distance is within sqrt(3) spacings of p's (the distance is 1-Lipschitz), so the
      // interpolation overstates it by at most that: reach that much further before giving up.
      const double slack = std::sqrt(3.0) * f.spacing;
      const bool in_grid = sampleField(f, c, INFINITY, &distance, &gradient);
      // Outside the grid is outside the mesh, at least the band away; the field's clamped values
      // beyond the band say only which side p is on.
      if (in_grid ? distance >= reach + slack : reach <= f.band) return out;
      Vector3 on_surface;
      const bool near = in_grid && std::abs(distance) < f.band - slack;
      if (near && shape.triangles && !f.nearest.empty() &&
          nearestOnMesh(f, *shape.triangles, c, distance, &distance, &normal, &on_surface)) {
      } else if (shape.triangles) {
        // The exact nearest surface, however far (a large sphere's centre, a point deep inside).
        const bool inside_mesh = in_grid && distance < 0.0;
        const MeshPoint m = nearestOnSurface(*shape.triangles, c, inside_mesh ? INFINITY : reach);
        if (!m.found) return out;
        distance = inside_mesh ? -m.distance : m.distance;
        if (m.distance > 1e-12) normal = (inside_mesh ? Vector3(m.point - c) : Vector3(c - m.point)) / m.distance;
        else normal = triangleNormal(*shape.triangles, m.triangle);
        on_surface = m.point;
      } else {
        if (!in_grid) return out;
        const double g = gradient.norm();
        if (!(g > 1e-9)) return out;  // a flat spot deep inside: no direction to push
        normal = gradient / g;
        on_surface = c - normal * distance;
      }
      if (distance >= reach) return out;
      out.valid = true;
      out.distance = distance;
      out.normal = pose.R * normal;
      out.surface = pose.act(on_surface);
      return out;
    }
  }
  out.valid = true;
  out.distance = inside ? -(surface - c).norm() : (c - surface).norm();
  out.normal = pose.R * normal;
  out.surface = pose.act(surface);
  return out;
}

}  // namespace igms
