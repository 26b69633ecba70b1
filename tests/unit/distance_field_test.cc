// The distance field of a mesh without external data: a unit cube (closed,
// 12 triangles) against its exact signed distance, and the on-disk cache
// (the same field back, a damaged file rebuilt, no cache folder no failure).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include "core/geometry/tip_contact.h"
#include "core/model_io/distance_field_builder.h"
#include "core/model_io/distance_field_cache.h"

namespace igms {
namespace {

namespace fs = std::filesystem;

TriangleMesh cube(double h) {  // [-h, h]^3, outward-wound
  TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.emplace_back(i & 1 ? h : -h, i & 2 ? h : -h, i & 4 ? h : -h);
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

double cubeDistance(const Vector3& p, double h) {  // the exact signed distance to the box
  const Vector3 q = p.cwiseAbs() - Vector3::Constant(h);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

// With the mesh's triangles the query is exact near the surface (the nearest
// triangles of the cell's corners); with the field alone (a description whose
// triangles are not kept) it interpolates, within 1 mm and 1 degree on faces.
void checkCube(bool with_triangles, double distance_bound, double angle_bound) {
  const double h = 0.05;
  const TriangleMesh mesh = cube(h);
  CollisionShape shape;
  shape.kind = CollisionShape::Kind::Mesh;
  shape.field = std::make_shared<const DistanceField>(buildDistanceField(mesh, 0.002, 0.015));
  if (with_triangles) shape.triangles = std::make_shared<const TriangleMesh>(mesh);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-h - 0.012, h + 0.012);
  double worst = 0.0, worst_angle = 0.0;
  int n = 0;
  for (int k = 0; k < 20000 && n < 2000; ++k) {
    const Vector3 p(u(rng), u(rng), u(rng));
    const double exact = cubeDistance(p, h);
    if (std::abs(exact) > 0.012) continue;
    EXPECT_NEAR(exactSignedDistance(mesh, p), exact, 1e-12);
    const TipContact c = tipContact(shape, SE3(), p, 0.05);
    ASSERT_TRUE(c.touching);
    worst = std::max(worst, std::abs((0.05 - c.depth) - exact));
    // On a face, away from its edges by 2 spacings: the face normal.
    const Vector3 a = p.cwiseAbs();
    int axis;
    a.maxCoeff(&axis);
    Vector3 rest = a;
    rest[axis] = 0;
    if (rest.maxCoeff() < h - 0.004 && exact > 0.001) {
      const Vector3 face = Vector3::Unit(axis) * (p[axis] > 0 ? 1.0 : -1.0);
      worst_angle = std::max(worst_angle, std::acos(std::clamp(c.normal.dot(face), -1.0, 1.0)) * 180 / M_PI);
    }
    ++n;
  }
  EXPECT_EQ(n, 2000);
  std::printf("cube, %s: worst distance error %.3g m, worst normal on faces %.3g deg\n",
              with_triangles ? "exact near the surface" : "field alone", worst, worst_angle);
  EXPECT_LT(worst, distance_bound) << "against the exact distance";
  EXPECT_LT(worst_angle, angle_bound) << "flat faces: the face's normal";
  // Far away, outside the grid: nothing to touch.
  EXPECT_FALSE(tipContact(shape, SE3(), Vector3(1, 0, 0), 0.01).touching);
}

TEST(DistanceField, CubeAgainstItsExactDistanceAndNormals) {
  checkCube(false, 0.001, 1.0);
  checkCube(true, 1e-9, 1e-6);
}

TEST(DistanceField, TheCacheGivesTheSameFieldAndSurvivesDamage) {
  const fs::path dir = fs::temp_directory_path() / ("igms_field_cache_" + std::to_string(getpid()));
  fs::remove_all(dir);
  setenv("IGMS_CACHE_DIR", dir.c_str(), 1);
  const TriangleMesh mesh = cube(0.03);
  const uint64_t key = distanceFieldKey(mesh, 0.002, 0.015);
  EXPECT_NE(key, distanceFieldKey(mesh, 0.003, 0.015)) << "the settings are part of the key";
  EXPECT_FALSE(readCachedField(key));
  const DistanceField built = buildDistanceField(mesh, 0.002, 0.015);
  writeCachedField(key, built);
  const auto back = readCachedField(key);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->values, built.values);
  EXPECT_EQ(back->nearest, built.nearest);
  EXPECT_EQ(back->nx, built.nx);
  EXPECT_EQ(back->origin, built.origin);
  // A damaged file is not read.
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) fs::resize_file(e.path(), 100);
  EXPECT_FALSE(readCachedField(key));
  // No usable folder: nothing cached, nothing fails.
  setenv("IGMS_CACHE_DIR", "/proc/igms-no-such-folder", 1);
  writeCachedField(key, built);
  EXPECT_FALSE(readCachedField(key));
  unsetenv("IGMS_CACHE_DIR");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace igms
