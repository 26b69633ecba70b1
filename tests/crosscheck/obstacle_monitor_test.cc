// The server's obstacle monitor (FCL, server/collision) on the Panda's real
// collision geometry against an exact distance computed here: brute force
// over every triangle of every link mesh placed at the robot's pose (point to
// triangle, then minus the ball's radius; inside a closed mesh counts as a
// collision, by the generalised winding number), and the fingers' boxes. 300 balls at random around
// the arm. Also the finding this came from: a 4 cm ball that link 3's mesh
// passes through was reported collision-free, 35 cm away.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <random>

#include "core/model/closest_point_on_triangle.h"
#include "core/simulation/simulation.h"
#include "server/collision/collision_world.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

struct Exact {
  double distance = 1e9;  // surface distance minus the radius; < 0: touching
  std::string link;
};

// Σ solid angles / 4π over one mesh's triangles: 1 inside a closed outward-wound mesh, 0 outside.
double winding(const TriangleMesh& mesh, const SE3& X, const Vector3& p) {
  double total = 0;
  for (const auto& t : mesh.triangles) {
    const Vector3 a = X.act(mesh.vertices[static_cast<size_t>(t[0])]) - p,
                  b = X.act(mesh.vertices[static_cast<size_t>(t[1])]) - p,
                  c = X.act(mesh.vertices[static_cast<size_t>(t[2])]) - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    total += 2 * std::atan2(a.dot(b.cross(c)), la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
  }
  return total / (4 * M_PI);
}

Exact exactDistance(const Model& m, const std::vector<SE3>& poses, const Vector3& centre, double radius) {
  Exact best;
  for (size_t f = 0; f < m.frames.size(); ++f) {
    if (m.frames[f].body < 0) continue;  // fixed to the world: the monitor leaves the base out
    for (const CollisionShape& s : m.frames[f].collisions) {
      const SE3 X = poses[f] * s.placement;
      if (s.kind == CollisionShape::Kind::Box) {  // the fingers' boxes: clamp into the box
        const Vector3 local = X.R.transpose() * (centre - X.p), half = 0.5 * s.size;
        const Vector3 q = local.cwiseMax(-half).cwiseMin(half);
        const double gap = q == local ? -(half - local.cwiseAbs()).minCoeff() - radius : (local - q).norm() - radius;
        if (gap < best.distance) best = {gap, m.frames[f].name};
        continue;
      }
      if (!s.triangles) continue;
      double d = 1e9;
      for (const auto& t : s.triangles->triangles) {
        const Vector3 q = closestPointOnTriangle(centre, X.act(s.triangles->vertices[static_cast<size_t>(t[0])]),
                                                 X.act(s.triangles->vertices[static_cast<size_t>(t[1])]),
                                                 X.act(s.triangles->vertices[static_cast<size_t>(t[2])])).point;
        d = std::min(d, (q - centre).norm());
      }
      const double gap = winding(*s.triangles, X, centre) > 0.5 ? -d - radius : d - radius;
      if (gap < best.distance) best = {gap, m.frames[f].name};
    }
  }
  return best;
}

// The monitor against one ghost obstacle, as a scene's geometry world holds it.
CollisionReport checkGhost(const Model& m, const Obstacle& o, const std::vector<SE3>& poses) {
  const GeometryModel geometry(m, {}, {SceneShape{o.name, o.shape, 0, false}});
  CollisionWorld world(m, geometry);
  return world.check(poses);
}

TEST(ObstacleMonitor, ThePandasMeshesAgainstAnExactDistance) {
  if (!std::filesystem::exists(sourceDir() + "/third_party/example-robot-data/robots/panda_description"))
    GTEST_SKIP() << "example-robot-data not fetched (scripts/setup/fetch_robots.sh)";
  Simulation sim(loadScene(sourceDir() + "/scenes/panda_obstacle.yaml"));
  const Model& m = sim.model();
  const std::vector<SE3> poses = sim.linkPoses();
  // The finding: a 4 cm ball centred 0.7 cm from a vertex of link 3's mesh.
  const int link3 = m.frameIndex("panda_link3");
  const CollisionShape& mesh3 = m.frame(link3).collisions.at(0);
  ASSERT_TRUE(mesh3.triangles);
  const Vector3 vertex = (poses[static_cast<size_t>(link3)] * mesh3.placement).act(mesh3.triangles->vertices[0]);
  {
    Obstacle ball;
    ball.name = "ball";
    ball.shape.kind = CollisionShape::Kind::Sphere;
    ball.shape.size = Vector3(0.02, 0, 0);
    ball.shape.placement = fromXyzRpy(vertex + Vector3(0.007, 0, 0), Vector3::Zero());
    const CollisionReport r = checkGhost(m, ball, poses);
    EXPECT_TRUE(r.in_collision) << "the ball holds a vertex of link 3's mesh";
    EXPECT_EQ(r.min_distance, 0.0);
  }
  // Random balls around the arm: FCL's distance against the exact one.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> around(-0.6, 0.6), radius(0.01, 0.05), near(-0.04, 0.04);
  std::vector<const CollisionShape*> meshes;
  std::map<const CollisionShape*, int> owner;
  for (size_t f = 0; f < m.frames.size(); ++f)
    for (const CollisionShape& s : m.frames[f].collisions)
      if (s.triangles && m.frames[f].body >= 0) {
        meshes.push_back(&s);
        owner[&s] = static_cast<int>(f);
      }
  const Vector3 middle = poses[static_cast<size_t>(m.frameIndex("panda_link4"))].p;
  double worst = 0.0;
  int touching = 0, apart = 0, agree = 0;
  for (int k = 0; k < 300; ++k) {
    Obstacle ball;
    ball.name = "ball";
    ball.shape.kind = CollisionShape::Kind::Sphere;
    ball.shape.size = Vector3(radius(rng), 0, 0);
    Vector3 centre = middle + Vector3(around(rng), around(rng), around(rng));
    if (k % 2) {  // every other ball near the surface: a vertex of a link's mesh, up to 4 cm off
      const CollisionShape& s = *meshes[std::uniform_int_distribution<size_t>(0, meshes.size() - 1)(rng)];
      const auto& vs = s.triangles->vertices;
      const Vector3 v = vs[std::uniform_int_distribution<size_t>(0, vs.size() - 1)(rng)];
      centre = (poses[static_cast<size_t>(owner.at(&s))] * s.placement).act(v) + Vector3(near(rng), near(rng), near(rng));
    }
    ball.shape.placement = fromXyzRpy(centre, Vector3::Zero());
    const CollisionReport r = checkGhost(m, ball, poses);
    const Exact e = exactDistance(m, poses, ball.shape.placement.p, ball.shape.size[0]);
    if (std::abs(e.distance) < 1e-4) continue;  // grazing: either answer is right
    if ((e.distance < 0) != r.in_collision)
      ADD_FAILURE() << "ball " << k << " (radius " << ball.shape.size[0] << "): exact " << e.distance << " at "
                    << e.link << ", the monitor " << r.min_distance << " at " << r.closest_link;
    if (e.distance < 0) {
      ++touching;
      agree += r.in_collision;
    } else {
      ++apart;
      agree += !r.in_collision;
      worst = std::max(worst, std::abs(r.min_distance - e.distance));
      EXPECT_EQ(r.closest_link, e.link) << "ball " << k;
    }
  }
  std::printf("obstacle monitor on the Panda's meshes: %d balls touching, %d apart, %d agree; distance error at most "
              "%.2e m\n", touching, apart, agree, worst);
  EXPECT_EQ(agree, touching + apart);
  EXPECT_GT(touching, 30);
  EXPECT_GT(apart, 100);
  EXPECT_LT(worst, 1e-5);
}

}  // namespace
}  // namespace igms::test
