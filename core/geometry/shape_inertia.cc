#include "core/geometry/shape_inertia.h"

#include <cmath>
#include <stdexcept>

#include "core/geometry/shape_kind.h"

namespace igms {

MassProperties shapeMassProperties(const CollisionShape& s, const TriangleMesh* mesh) {
  MassProperties out;
  Matrix3& I = out.inertia;
  switch (s.kind) {
    case CollisionShape::Kind::Box: {
      const double a = s.size[0], b = s.size[1], c = s.size[2];
      out.volume = a * b * c;
      I.diagonal() = (out.volume / 12.0) * Vector3(b * b + c * c, a * a + c * c, a * a + b * b);
      return out;
    }
    case CollisionShape::Kind::Sphere: {
      const double r = s.size[0];
      out.volume = 4.0 / 3.0 * M_PI * r * r * r;
      I.diagonal().setConstant(0.4 * out.volume * r * r);
      return out;
    }
    case CollisionShape::Kind::Cylinder: {
      const double r = s.size[0], L = s.size[1];
      out.volume = M_PI * r * r * L;
      const double m = out.volume;
      I.diagonal() = Vector3(m * (3 * r * r + L * L) / 12.0, m * (3 * r * r + L * L) / 12.0, 0.5 * m * r * r);
      return out;
    }
    case CollisionShape::Kind::Capsule: {
      // A cylinder and two hemispheres (together a sphere), each hemisphere's centre of mass 3r/8
      // beyond its end of the cylinder.
      const double r = s.size[0], L = s.size[1];
      const double mc = M_PI * r * r * L, mh = 4.0 / 3.0 * M_PI * r * r * r;
      out.volume = mc + mh;
      const double across = mc * (L * L / 12.0 + r * r / 4.0) + mh * (0.4 * r * r + L * L / 4.0 + 3.0 * L * r / 8.0);
      I.diagonal() = Vector3(across, across, 0.5 * mc * r * r + 0.4 * mh * r * r);
      return out;
    }
    case CollisionShape::Kind::Mesh: {
      if (!mesh) throw std::invalid_argument("a mesh's mass properties need its triangles");
      double V = 0.0;
      Vector3 first = Vector3::Zero();
      Matrix3 second = Matrix3::Zero();  // integral of x x^T over the volume
      for (const auto& t : mesh->triangles) {
        const Vector3 &a = mesh->vertices[static_cast<size_t>(t[0])], &b = mesh->vertices[static_cast<size_t>(t[1])],
                      &c = mesh->vertices[static_cast<size_t>(t[2])];
        const double det = a.dot(b.cross(c));  // 6 x the signed volume of the tetrahedron (0, a, b, c)
        V += det / 6.0;
        first += det / 24.0 * (a + b + c);
        const Vector3 sum = a + b + c;
        second += det / 120.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
      }
      if (!(std::abs(V) > 1e-15)) throw std::invalid_argument("the mesh encloses no volume (is it closed?)");
      if (V < 0.0) {  // wound inward: the same solid
        V = -V;
        first = -first;
        second = -second;
      }
      out.volume = V;
      out.com = first / V;
      const Matrix3 about_origin = second.trace() * Matrix3::Identity() - second;
      const Vector3& c = out.com;
      I = about_origin - V * (c.squaredNorm() * Matrix3::Identity() - c * c.transpose());
      return out;
    }
    case CollisionShape::Kind::Plane: break;
  }
  throw std::invalid_argument(std::string("a ") + shapeKindName(s.kind) + " has no mass properties");
}

}  // namespace igms
