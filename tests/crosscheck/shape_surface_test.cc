// A shape's surface as triangles (core/geometry/shape_surface.h), what FCL, ODE
// and the page take for a kind they lack, against the shape it stands for:
//   every kind's surface is closed (each edge once each way), wound outward and
//   has its vertices on the exact surface (igms's point query: 1e-12 m);
//   its volume, centre and inertia (divergence theorem) fall short of the
//   primitive's closed forms by no more than the inscribed polyhedron's bound,
//   3 (1 - cos rho) with rho the widest triangle's angular half-diagonal, and a
//   box's is exact;
//   in FCL, a sphere's distance to the surface's BVH (fclSurface) exceeds its
//   distance to FCL's own primitive by 0 to the sagitta, from 200 directions;
//   and the monitor's form (fclShape) of a mesh is the mesh's own triangles.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>
#include <utility>

#include "core/geometry/point_query.h"
#include "core/geometry/shape_bounds.h"
#include "core/geometry/shape_inertia.h"
#include "core/geometry/shape_kind.h"
#include "core/geometry/shape_surface.h"
#include "server/collision/fcl_shape.h"

namespace igms {
namespace {

using Kind = CollisionShape::Kind;

// Every primitive kind, sized by distinct numbers from 0.07 m on (as the table reads them).
std::vector<CollisionShape> primitives() {
  std::vector<CollisionShape> out;
  for (const ShapeKindInfo& kind : shapeKinds()) {
    if (!kind.primitive) continue;
    CollisionShape s;
    s.kind = kind.kind;
    double x = 0.07;
    for (const ShapeDimension& d : kind.dimensions)
      for (int i = 0; d.key && i < d.count; ++i, x += 0.03) s.size[d.at + i] = x;
    out.push_back(s);
  }
  return out;
}

// 3 (1 - cos rho): a round shape's inscribed polyhedron holds the shape shrunk by 1 - cos rho (rho: the
// angle a triangle spans from its circumcentre's direction), and volume goes as the cube of it.
double volumeShortfallBound(int segments) {
  const double rho = std::sqrt(2.0) * M_PI / segments;
  return 3.0 * (1.0 - std::cos(rho));
}

TEST(ShapeSurface, EveryKindIsClosedOutwardAndOnItsSurface) {
  const auto all = primitives();
  ASSERT_EQ(all.size(), 4u) << "box, cylinder, sphere, capsule";
  for (const CollisionShape& s : all) {
    for (int segments : {8, 24, 64}) {
      const TriangleMesh m = shapeSurface(s, segments);
      const char* name = shapeKindName(s.kind);
      ASSERT_FALSE(m.triangles.empty()) << name;
      std::map<std::pair<int, int>, int> edges;
      for (const auto& t : m.triangles)
        for (int e = 0; e < 3; ++e) ++edges[{t[e], t[(e + 1) % 3]}];
      for (const auto& [edge, count] : edges) {
        ASSERT_EQ(count, 1) << name << ": edge " << edge.first << "-" << edge.second << " twice the same way";
        ASSERT_EQ(edges.count({edge.second, edge.first}), 1u) << name << ": edge with no twin: open surface";
      }
      for (const auto& t : m.triangles) {
        const Vector3 n = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
        ASSERT_GT(n.norm(), 1e-12) << name << ": a degenerate triangle";
      }
      for (const Vector3& v : m.vertices)
        ASSERT_NEAR(pointQuery(s, SE3::Identity(), v).distance, 0.0, 1e-12) << name << " vertex " << v.transpose();

      const MassProperties exact = shapeMassProperties(s);
      CollisionShape as_mesh;
      as_mesh.kind = Kind::Mesh;
      const MassProperties tessellated = shapeMassProperties(as_mesh, &m);
      const double shortfall = 1.0 - tessellated.volume / exact.volume;
      const double bound = s.kind == Kind::Box ? 1e-12 : volumeShortfallBound(segments);
      std::printf("%-8s %2d segments: %4zu triangles, volume short by %.2e (bound %.2e)\n", name, segments,
                  m.triangles.size(), shortfall, bound);
      EXPECT_GE(shortfall, -1e-12) << name << ": an inscribed surface holds less than the shape";
      EXPECT_LE(shortfall, bound) << name;
      EXPECT_LT(tessellated.com.norm(), 1e-12 * boundingRadius(s)) << name;
      EXPECT_LE((tessellated.inertia - exact.inertia).norm(), (5.0 / 3.0) * bound * exact.inertia.norm()) << name;
    }
  }
  CollisionShape plane;
  plane.kind = Kind::Plane;
  EXPECT_TRUE(shapeSurface(plane).triangles.empty()) << "a plane is unbounded: no surface";
}

TEST(ShapeSurface, AMeshIsItsOwnTriangles) {
  CollisionShape box;
  box.kind = Kind::Box;
  box.size = Vector3(0.1, 0.2, 0.3);
  CollisionShape mesh;
  mesh.kind = Kind::Mesh;
  EXPECT_TRUE(shapeSurface(mesh).triangles.empty()) << "a mesh read without its triangles";
  EXPECT_EQ(fclShape(mesh), nullptr);
  auto triangles = std::make_shared<TriangleMesh>(shapeSurface(box));
  mesh.triangles = triangles;
  const TriangleMesh m = shapeSurface(mesh);
  EXPECT_EQ(m.vertices, triangles->vertices);
  EXPECT_EQ(m.triangles, triangles->triangles);
  const auto fcl_mesh = std::dynamic_pointer_cast<fcl::BVHModel<fcl::OBBRSSd>>(fclShape(mesh));
  ASSERT_NE(fcl_mesh, nullptr) << "the monitor takes a mesh as FCL's BVH";
  EXPECT_EQ(fcl_mesh->num_tris, static_cast<int>(triangles->triangles.size()));
  EXPECT_EQ(fcl_mesh->num_vertices, static_cast<int>(triangles->vertices.size()));
}

TEST(ShapeSurface, InFclTheSurfaceIsThePrimitiveWithinItsSagitta) {
  std::mt19937 rng(46);
  std::normal_distribution<double> normal;
  const fcl::Sphered probe(0.01);
  for (const CollisionShape& s : primitives()) {
    const auto native = fclShape(s);
    const auto surface = fclSurface(s);
    ASSERT_NE(native, nullptr);
    ASSERT_NE(surface, nullptr);
    ASSERT_NE(native->getObjectType(), fcl::OT_BVH) << "FCL has this kind: its own primitive";
    // A round kind's surface is short of it by its radius (size[0]) times 1 - cos rho.
    const double sagitta = s.kind == Kind::Box ? 0.0 : s.size[0] * (1.0 - std::cos(std::sqrt(2.0) * M_PI / 24));
    double widest = 0.0;
    for (int k = 0; k < 200; ++k) {
      const Vector3 u = Vector3(normal(rng), normal(rng), normal(rng)).normalized();
      fcl::Transform3d at = fcl::Transform3d::Identity();
      at.translation() = u * (boundingRadius(s) + 0.05);
      const fcl::Transform3d origin = fcl::Transform3d::Identity();
      fcl::DistanceRequestd request;
      request.enable_nearest_points = false;
      fcl::DistanceResultd to_native, to_surface;
      fcl::distance(native.get(), origin, &probe, at, request, to_native);
      fcl::distance(surface.get(), origin, &probe, at, request, to_surface);
      const double gap = to_surface.min_distance - to_native.min_distance;
      widest = std::max(widest, gap);
      ASSERT_GE(gap, -1e-6) << shapeKindName(s.kind) << ": the inscribed surface is nearer than the shape";
      ASSERT_LE(gap, sagitta + 1e-6) << shapeKindName(s.kind) << " from " << u.transpose();
    }
    std::printf("%-8s FCL: surface farther than the primitive by up to %.2e m (sagitta %.2e m)\n",
                shapeKindName(s.kind), widest, sagitta);
  }
}

}  // namespace
}  // namespace igms
