// Bodies on meshes against the exact distance to the mesh's triangles (exactSignedDistance: every
// triangle, by brute force: neither the mesh's distance field nor its hierarchy) and the analytic rest
// height, through the whole step (scene, contact detection, solve):
//   a sphere of every size from 1 mm to 20 cm, a box, a capsule and a cylinder lying on their sides, a
//   cylinder standing, and a mesh body, each at rest on a closed mesh cube (models/meshes/cube.obj):
//   at the height its shape says, overlap at most 0.1 mm (a sphere over 1 cm used to sink 1-2 cm: the
//   field is exact only within its 1.5 cm band, and its centre was farther);
//   each of them dropped onto the cube at 2 m/s: overlap at most 1 mm through the impact;
//   a ball dropped into a non-convex bowl (models/meshes/bowl.obj): it lands in the cavity, not on the
//   convex hull's lid, overlap at most 1 mm through the impact and 0.1 mm at rest;
//   a ball wedged between two mesh walls (the U channel's slot): held by both, not through either.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <vector>

#include "core/model/environment_model.h"
#include "core/model_io/distance_field_builder.h"
#include "core/model_io/mesh_reader.h"
#include "core/simulation/simulation.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

constexpr double kTop = 0.4;  // the cube (0.4 m, centred at z = 0.2) has its top here

Scene sceneText(const std::string& yaml) { return parseScene(yaml, "test.yaml", test::sourceDir() + "/scenes"); }

const TriangleMesh& mesh(const char* name) {
  static std::map<std::string, TriangleMesh> loaded;
  auto it = loaded.find(name);
  if (it == loaded.end())
    it = loaded.emplace(name, loadTriangleMesh(test::sourceDir() + "/models/meshes/" + name, Vector3::Ones())).first;
  return it->second;
}

// A body's surface as points and radii (a sphere about each point): what overlaps the mesh is where
// the exact signed distance from a point falls below its radius.
struct Probe {
  std::vector<Vector3> points;  // body frame
  std::vector<double> radius;
};

Probe probeOf(const CollisionShape& s) {
  Probe p;
  auto add = [&](const Vector3& x, double r) {
    p.points.push_back(s.placement.act(x));  // in the body frame
    p.radius.push_back(r);
  };
  const int n = 12;
  switch (s.kind) {
    case CollisionShape::Kind::Sphere: add(Vector3::Zero(), s.size[0]); break;
    case CollisionShape::Kind::Capsule:
      for (int k = 0; k <= n; ++k) add(Vector3(0, 0, s.size[1] * (double(k) / n - 0.5)), s.size[0]);
      break;
    case CollisionShape::Kind::Box:
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j)
          for (int k = 0; k <= n; ++k)
            if (i == 0 || j == 0 || k == 0 || i == n || j == n || k == n)
              add(s.size.cwiseProduct(Vector3(double(i) / n - 0.5, double(j) / n - 0.5, double(k) / n - 0.5)), 0.0);
      break;
    case CollisionShape::Kind::Cylinder:
      for (int a = 0; a < 8 * n; ++a)
        for (int k = 0; k <= n; ++k) {
          const double t = 2 * M_PI * a / (8 * n);
          add(Vector3(s.size[0] * std::cos(t), s.size[0] * std::sin(t), s.size[1] * (double(k) / n - 0.5)), 0.0);
        }
      break;
    case CollisionShape::Kind::Mesh:
      for (const Vector3& v : s.triangles->vertices) add(v, 0.0);
      break;
    case CollisionShape::Kind::Plane: break;
  }
  return p;
}

// How deep the body (part `name`) is in the fixed mesh at `mesh_pose` (0: not at all), exactly.
double overlap(const Simulation& sim, const std::string& name, const Probe& probe, const TriangleMesh& fixed,
               const SE3& mesh_pose) {
  for (const ModelPart& part : sim.model().parts) {
    if (part.name != name) continue;
    const FreeBodyState b = freeBodyState(part, sim.q(), sim.v());
    double deepest = 0.0;
    for (size_t k = 0; k < probe.points.size(); ++k) {
      const Vector3 world = b.p + b.R * probe.points[k];
      const double d = exactSignedDistance(fixed, mesh_pose.R.transpose() * (world - mesh_pose.p)) - probe.radius[k];
      deepest = std::max(deepest, -d);
    }
    return deepest;
  }
  ADD_FAILURE() << "no body " << name;
  return 0.0;
}

const CollisionShape& shapeOf(const Simulation& sim, const std::string& name) {
  for (const Frame& f : sim.model().frames)
    if (f.name == name && !f.collisions.empty()) return f.collisions.front();
  throw std::runtime_error("no frame " + name);
}

struct Run {
  double impact_overlap = 0.0, rest_overlap = 0.0, rest_height = 0.0;
  int rest_contacts = 0;
};

// The body `shape_yaml` (its shape keys) above the cube, its lowest point `clearance` above the top,
// launched down at `speed`: overlap through the first second, then at rest for another.
Run onTheCube(const std::string& shape_yaml, double half_height, double clearance, double speed, const char* rpy) {
  char yaml[1024];
  std::snprintf(yaml, sizeof yaml,
                "gravity: [0, 0, -9.81]\nmaterials: {m: {friction: 0.8}}\n"
                "obstacles: [{name: block, shape: mesh, file: ../models/meshes/cube.obj, xyz: [0, 0, 0.2], solid: true, "
                "material: m}]\n"
                "bodies: [{name: b, %s, mass: 0.5, xyz: [0.013, -0.021, %.17g], rpy: %s, v: [0, 0, %.17g], material: m}]\n",
                shape_yaml.c_str(), kTop + half_height + clearance, rpy, -speed);
  Simulation sim(sceneText(yaml));
  const Probe probe = probeOf(shapeOf(sim, "b"));
  const SE3 cube{Matrix3::Identity(), Vector3(0, 0, 0.2)};
  Run r;
  for (int k = 1; k <= 2000; ++k) {
    EXPECT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
    const double o = overlap(sim, "b", probe, mesh("cube.obj"), cube);
    if (k <= 1000) r.impact_overlap = std::max(r.impact_overlap, o);
    else r.rest_overlap = std::max(r.rest_overlap, o);
  }
  r.rest_height = sim.q()[2];
  r.rest_contacts = sim.contacts().n;
  return r;
}

void expectRests(const std::string& what, const std::string& shape_yaml, double half_height,
                 const char* rpy = "[0, 0, 0]") {
  const Run still = onTheCube(shape_yaml, half_height, 0.002, 0.0, rpy);
  const Run hit = onTheCube(shape_yaml, half_height, 0.05, 2.0, rpy);
  std::printf("%-28s at rest %+.2e m from its height, overlap %.2e m (%d contacts); after a 2 m/s impact %.2e m, "
              "at rest %+.2e m\n",
              what.c_str(), still.rest_height - (kTop + half_height), still.rest_overlap, still.rest_contacts,
              hit.impact_overlap, hit.rest_height - (kTop + half_height));
  EXPECT_NEAR(still.rest_height, kTop + half_height, 1e-4) << what;
  EXPECT_LE(still.rest_overlap, 1e-4) << what;
  EXPECT_LE(still.impact_overlap, 1e-4) << what << ": released 2 mm above";
  EXPECT_LE(hit.impact_overlap, 1e-3) << what << ": a 2 m/s impact";
  EXPECT_NEAR(hit.rest_height, kTop + half_height, 1e-4) << what << ": at rest after the impact";
}

TEST(MeshRest, SpheresOfEverySizeRestOnAMeshCube) {
  for (const double r : {0.001, 0.005, 0.01, 0.03, 0.06, 0.2}) {
    char shape[128];
    std::snprintf(shape, sizeof shape, "shape: sphere, radius: %g", r);
    expectRests("sphere r " + std::to_string(r), shape, r);
  }
}

TEST(MeshRest, ABoxACapsuleAndACylinderRestOnAMeshCube) {
  expectRests("box", "shape: box, size: [0.1, 0.08, 0.06]", 0.03);
  expectRests("capsule lying", "shape: capsule, radius: 0.03, length: 0.15", 0.03, "[1.5707963267948966, 0, 0.3]");
  expectRests("cylinder lying", "shape: cylinder, radius: 0.05, length: 0.1", 0.05, "[1.5707963267948966, 0, 0.7]");
  expectRests("cylinder standing", "shape: cylinder, radius: 0.05, length: 0.1", 0.05);
}

TEST(MeshRest, AMeshBodyRestsOnAMeshCube) {
  // The cube's own mesh at a quarter of its size: 0.1 m, its corners and the samples of its faces on the
  // larger cube's field.
  expectRests("mesh cube on a mesh cube", "shape: mesh, file: ../models/meshes/cube.obj, scale: [0.25, 0.25, 0.25]",
              0.05);
}

TEST(MeshRest, ABallDroppedIntoABowlLandsInItsCavity) {
  // bowl.obj: the cavity's lowest point is at z = 0.05, its rim at 0.2; the convex hull would hold a
  // ball at the rim.
  const double r = 0.03;
  Simulation sim(sceneText(
      "obstacles: [{name: bowl, shape: mesh, file: ../models/meshes/bowl.obj, xyz: [0, 0, 0], solid: true}]\n"
      "bodies: [{name: ball, shape: sphere, radius: 0.03, mass: 0.2, xyz: [0, 0, 0.4]}]\n"));
  const Probe probe = probeOf(shapeOf(sim, "ball"));
  double impact = 0.0, rest = 0.0, fastest = 0.0;
  for (int k = 1; k <= 2500; ++k) {
    ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
    const double o = overlap(sim, "ball", probe, mesh("bowl.obj"), SE3::Identity());
    fastest = std::max(fastest, -sim.v()[2]);
    (k <= 1500 ? impact : rest) = std::max(k <= 1500 ? impact : rest, o);
  }
  const double z = sim.q()[2];
  std::printf("ball into the bowl: lands at %.2f m/s, overlap %.2e m through the impact, %.2e m at rest, centre at "
              "z %.6f (cavity bottom + r: %.6f)\n",
              fastest, impact, rest, z, 0.05 + r);
  EXPECT_GT(fastest, 2.0) << "an impact of over 2 m/s";
  EXPECT_LE(impact, 1e-3);
  EXPECT_LE(rest, 1e-4);
  EXPECT_NEAR(z, 0.05 + r, 2e-3) << "in the cavity (facets aside), not on the hull's lid at z 0.23";
}

TEST(MeshRest, ABallWedgedInAGrooveIsHeldByBothWalls) {
  // The U channel (0.3 x 0.2 x 0.2 m, its slot 0.1 m wide and 0.15 m deep, open upward, along y): a ball
  // of radius 0.06 does not fit the slot and sits on its two top edges, held by both walls at once.
  Simulation sim(sceneText(
      "obstacles: [{name: u, shape: mesh, file: ../models/meshes/u_channel.obj, xyz: [0, 0, 0.1], solid: true}]\n"
      "bodies: [{name: ball, shape: sphere, radius: 0.06, mass: 0.5, xyz: [0.002, 0.01, 0.25]}]\n"));
  const Probe probe = probeOf(shapeOf(sim, "ball"));
  double worst = 0.0;
  for (int k = 1; k <= 2000; ++k) {
    ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
    worst = std::max(worst, overlap(sim, "ball", probe, mesh("u_channel.obj"), SE3{Matrix3::Identity(), Vector3(0, 0, 0.1)}));
  }
  // Resting on the slot's two top edges (x = +-0.05, z = 0.2): the centre sqrt(r^2 - 0.05^2) above them.
  const double expected = 0.2 + std::sqrt(0.06 * 0.06 - 0.05 * 0.05);
  std::printf("ball on the groove's edges: centre at x %.2e, z %.6f (expected %.6f), %d contacts, overlap %.2e m\n",
              sim.q()[0], sim.q()[2], expected, sim.contacts().n, worst);
  EXPECT_NEAR(sim.q()[2], expected, 1e-4);
  EXPECT_NEAR(sim.q()[0], 0.0, 1e-4) << "centred between the walls";
  EXPECT_EQ(sim.contacts().n, 2) << "one contact per wall";
  EXPECT_LE(worst, 1e-4);
}

TEST(MeshRest, APegInAUChannelSlotComesDownOntoItsFloor) {
  // A box peg lowered into the U channel's slot (0.1 m wide, 0.15 m deep, its floor 0.05 m below the
  // channel's origin), with the channel at three heights: a peg 0.5 mm narrower than the slot, one as
  // wide, and ones pressed in (0.2 and 0.4 mm wider: its corners inside both walls the whole way
  // down). One pair (peg, channel) then has points on both walls, normals that cancel when averaged:
  // averaged into one patch, the pressed peg fell through the channel's floor (to z -9.3 m in 1.5 s).
  // Each facing is now a patch of its own. Rigid bodies cannot say how hard an interference fit
  // squeezes, so the pressed peg need not stay up; it must come down onto the floor, not through it,
  // and stay there. The position correction used to push both walls' overlaps apart at once, which no
  // motion can: its pseudo-impulses grew to the sweep limit and turned the peg, which rattled in the
  // slot (channel at z 0, over 3 s: the 0.4 mm peg up to 10.7 mm off the floor after the first second
  // and 0.5 mm into it, 1,981 corrections at their limit; the 0.2 mm peg 2,272). Now each wall closes
  // half its excess over the other's: 0 and 3-10 corrections at their limit, the pegs centred.
  // The 0.2 mm peg still wobbles in place (up to 1.2e-3 rad a step, channel at z 0.37, 0.01 mm up or
  // down): a pair keeps four points (kMaxPairPoints), three of them with a wall's normal, so one corner
  // alone holds it on the floor. Its bounds below are the ones it meets.
  for (const double width : {0.0995, 0.1, 0.1002, 0.1004})
    for (const double at : {0.0, 0.1, 0.37}) {
      char yaml[768];
      std::snprintf(yaml, sizeof yaml,
                    "materials: {m: {friction: 0.5}}\n"
                    "obstacles: [{name: u, shape: mesh, file: ../models/meshes/u_channel.obj, xyz: [0, 0, %.17g], "
                    "solid: true, material: m}]\n"
                    "bodies: [{name: peg, shape: box, size: [%.17g, 0.06, 0.06], mass: 0.5, xyz: [0, 0, %.17g], "
                    "material: m}]\n",
                    at, width, at + 0.05);
      Simulation sim(sceneText(yaml));
      const double rest = -0.05 + 0.03;  // the slot's floor plus the peg's half height
      double lowest = 1.0, highest = -1.0, off_centre = 0.0;  // the last two after the first second
      for (int k = 1; k <= 3000; ++k) {
        ASSERT_TRUE(sim.step(nullptr)) << sim.divergenceReport();
        lowest = std::min(lowest, sim.q()[2] - at);
        if (k > 1000) {
          highest = std::max(highest, sim.q()[2] - at);
          off_centre = std::max(off_centre, std::abs(sim.q()[0]));
        }
      }
      std::printf("peg %.4f m wide in the 0.1 m slot, channel at z %.2f: ends %+.2e m from the floor, lowest %+.2e m, "
                  "highest after 1 s %+.2e m, off centre %.1e m, %lld corrections at their limit\n",
                  width, at, sim.q()[2] - at - rest, lowest - rest, highest - rest, off_centre,
                  static_cast<long long>(sim.contactStats().position_unconverged));
      EXPECT_GT(lowest, rest - 1e-4) << width << " at " << at << ": not into the floor";
      EXPECT_LT(highest, rest + 1e-4) << width << " at " << at << ": on the floor from the first second on";
      if (width <= 0.1) {
        EXPECT_NEAR(sim.q()[2] - at, rest, 1e-4) << width << " at " << at << ": on the floor";
      } else {
        EXPECT_LT(off_centre, 2e-5) << width << " at " << at << ": centred between the walls";
      }
      if (width == 0.1002) {  // wobbling on one corner (above)
        EXPECT_LE(sim.contactStats().position_unconverged, 20) << width << " at " << at;
      } else {
        EXPECT_LT(sim.v().norm(), 1e-3) << width << " at " << at << ": at rest";
        EXPECT_EQ(sim.contactStats().position_unconverged, 0) << width << " at " << at;
      }
    }
}

}  // namespace
}  // namespace igms
