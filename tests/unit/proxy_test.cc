// The tip's proxy (core/interaction/proxy.h) against analytic cases: a device
// dragged 10 cm "into" a 2 cm plate or a 2 cm link never takes the proxy out of
// the other side and never flips the spring (with friction: frictionless, it
// slides round the round link, as a frictionless ball would); on the ground the
// frictionless proxy slides with the device and the force is the wall's normal,
// with friction the force is on the cone's edge; a body that moves into the
// proxy carries it; a free proxy engages only at the surface; a jump frees it;
// an update allocates nothing.
#include <gtest/gtest.h>

#include "core/geometry/point_query.h"
#include "core/interaction/proxy.h"
#include "core/model/environment_model.h"
#include "core/simulation/simulation.h"
#include "tests/support/malloc_counter.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

constexpr double kRadius = 0.01;

CollisionShape shape(CollisionShape::Kind kind, const Vector3& size, const SE3& pose = SE3::Identity()) {
  CollisionShape s;
  s.kind = kind;
  s.size = size;
  s.placement = pose;
  return s;
}

// A world of fixed shapes only (no model frames).
std::vector<SceneShape> named(const std::vector<CollisionShape>& shapes) {
  std::vector<SceneShape> out;
  for (size_t k = 0; k < shapes.size(); ++k) out.push_back(SceneShape{"shape" + std::to_string(k), shapes[k], 0, true});
  return out;
}

struct FixedWorld {
  Model model = emptyEnvironment("proxy_test", "proxy_test", Vector3::Zero());
  GeometryModel world;
  GeometryData placed{world};
  explicit FixedWorld(const std::vector<CollisionShape>& shapes) : world(model, {}, named(shapes)) {
    placed.place(world, std::vector<SE3>{});
  }
  // The proxy's distance to the nearest shape's surface (negative: inside).
  double clearance(const Proxy& p) const {
    double d = 1e9;
    for (int g = 0; g < world.size(); ++g)
      d = std::min(d, pointQuery(*world.object(g).shape, placed.oMg[static_cast<size_t>(g)], p.position()).distance);
    return d;
  }
};

// Drags the device from `from` to `to` in steps of 0.5 mm (a hand at 0.5 m/s), one update each;
// returns the smallest clearance and the smallest spring component along `outward` while touching.
struct Drag {
  double min_clearance = 1e9, min_along = 1e9, last_along = 0.0;
  bool touched = false;
};
Drag drag(FixedWorld& w, Proxy& p, const Vector3& from, const Vector3& to, const Vector3& outward) {
  Drag out;
  const int n = static_cast<int>(std::ceil((to - from).norm() / 0.0005));
  for (int k = 0; k <= n; ++k) {
    const Vector3 device = from + (to - from) * (static_cast<double>(k) / n);
    p.update(w.world, w.placed, device, kRadius, false);
    out.min_clearance = std::min(out.min_clearance, w.clearance(p));
    if (p.touches() > 0) {
      out.touched = true;
      out.last_along = p.stretch(device).dot(outward);
      out.min_along = std::min(out.min_along, out.last_along);
    }
  }
  return out;
}

TEST(Proxy, ADevice10cmIntoA2cmPlateNeverTakesItThrough) {
  // A 2 cm plate, 30 cm square, top face at z = 0.01.
  FixedWorld w({shape(CollisionShape::Kind::Box, Vector3(0.3, 0.3, 0.02))});
  Proxy p(w.world);
  const Drag d = drag(w, p, Vector3(0.02, 0.01, 0.06), Vector3(0.02, 0.01, 0.01 - 0.10), Vector3::UnitZ());
  ASSERT_TRUE(d.touched);
  EXPECT_GE(d.min_clearance, kRadius - 1e-9) << "the proxy never entered the plate";
  EXPECT_GE(p.position().z(), 0.01 + kRadius - 1e-9) << "it is on the top face, not below the plate";
  EXPECT_GE(d.min_along, 0.0) << "the spring never pulls the hand into the plate (no flip)";
  EXPECT_NEAR(d.last_along, 0.10 + kRadius, 1e-9) << "the stretch is the device's depth below the proxy";
  EXPECT_LE((p.stretch(Vector3(0.02, 0.01, -0.09)) - Vector3(0, 0, 0.11)).norm(), 1e-9) << "and it is vertical";
}

TEST(Proxy, ADevice10cmIntoA2cmLinkNeverTakesItThroughOrFlipsTheForce) {
  // A link: a cylinder of radius 1 cm (2 cm thick) along x, and a capsule of the same size beside it.
  SE3 along_x;
  along_x.R = Eigen::AngleAxisd(M_PI / 2, Vector3::UnitY()).toRotationMatrix();
  SE3 capsule_pose = along_x;
  capsule_pose.p = Vector3(0.0, 0.5, 0.0);
  for (const CollisionShape& link : {shape(CollisionShape::Kind::Cylinder, Vector3(0.01, 0.3, 0), along_x),
                                     shape(CollisionShape::Kind::Capsule, Vector3(0.01, 0.3, 0), capsule_pose)}) {
    FixedWorld w({link});
    Proxy p(w.world, 0.5);
    const Vector3 over = link.placement.p + Vector3(0.03, 0.002, 0.05);  // slightly off the axis: no symmetry
    const Drag d = drag(w, p, over, over - Vector3(0, 0, 0.15), Vector3::UnitZ());
    ASSERT_TRUE(d.touched);
    EXPECT_GE(d.min_clearance, kRadius - 1e-9);
    EXPECT_GT(p.position().z(), link.placement.p.z()) << "the proxy is still above the link";
    EXPECT_GE(d.min_along, 0.0) << "never flipped";
    EXPECT_GT(d.last_along, 0.09) << "the stretch grew with the device's depth";
    Proxy frictionless(w.world);
    drag(w, frictionless, over, over - Vector3(0, 0, 0.15), Vector3::UnitZ());
    EXPECT_LT(frictionless.position().z(), link.placement.p.z()) << "without friction it slid round the link";
    EXPECT_GE(w.clearance(frictionless), kRadius - 1e-9) << "round it, never through it";
  }
}

TEST(Proxy, WithFrictionTheWallsForceIsOnTheConesEdgeWhileItSlides) {
  FixedWorld w({shape(CollisionShape::Kind::Plane, Vector3::Zero())});
  const double mu = 0.5;
  Proxy p(w.world, mu);
  for (int k = 0; k <= 100; ++k) p.update(w.world, w.placed, Vector3(0, 0, 0.05 - 0.001 * k), kRadius, false);
  const Vector3 stuck = p.position();
  p.update(w.world, w.placed, Vector3(0.01, 0, -0.05), kRadius, false);  // 1 cm aside, 6 cm deep: inside the cone
  EXPECT_EQ(p.position(), stuck) << "static: it sticks";
  for (int k = 0; k <= 200; ++k) p.update(w.world, w.placed, Vector3(0.01 + 0.0005 * k, 0, -0.05), kRadius, false);
  const Vector3 f = p.stretch(Vector3(0.11, 0, -0.05));  // sliding: tangential = mu * normal, against the motion
  EXPECT_NEAR(f.z(), 0.06, 1e-12);
  EXPECT_NEAR(-f.x(), mu * f.z(), 1e-9);
  EXPECT_NEAR(p.position().z(), kRadius, 1e-12);
}

TEST(Proxy, OnTheGroundItSlidesWithTheDeviceAndTheForceIsTheWalls) {
  CollisionShape ground = shape(CollisionShape::Kind::Plane, Vector3::Zero());
  FixedWorld w({ground});
  Proxy p(w.world);
  p.update(w.world, w.placed, Vector3(0, 0, 0.05), kRadius, false);
  for (int k = 0; k <= 100; ++k) p.update(w.world, w.placed, Vector3(0, 0, 0.05 - 0.001 * k), kRadius, false);
  // 4.5 cm below the floor, then along it, then diagonally.
  for (int k = 0; k <= 200; ++k) {
    const Vector3 device(0.001 * k, 0.0005 * k, -0.045);
    p.update(w.world, w.placed, device, kRadius, false);
    ASSERT_EQ(p.touches(), 1);
    EXPECT_LE((p.position() - Vector3(device.x(), device.y(), kRadius)).norm(), 1e-12) << k;
    EXPECT_LE((p.stretch(device) - Vector3(0, 0, 0.055)).norm(), 1e-12) << "normal, and the device's depth";
  }
  EXPECT_EQ(p.deepest(w.world, Vector3(0.2, 0.1, -0.045), true), -1) << "the ground does not move: no push";
  EXPECT_EQ(p.deepest(w.world, Vector3(0.2, 0.1, -0.045), false), 0);
}

// A small tip moves at most kMaxSubsteps half-radius steps a cycle: a device 4 cm along the floor in one
// cycle (under kJump: a fast hand, not a jump) takes a 2 mm tip's proxy three cycles, and the two it
// ran out of substeps are counted (the server's status and the client's report them).
TEST(Proxy, ACycleCutShortByTheSubstepBudgetIsCountedAndCaughtUpNext) {
  constexpr double r = 0.002, per_cycle = Proxy::kMaxSubsteps * 0.5 * r;  // 16 mm
  FixedWorld w({shape(CollisionShape::Kind::Plane, Vector3::Zero())});
  Proxy p(w.world);
  p.update(w.world, w.placed, Vector3(0, 0, 0.01), r, false);
  for (int k = 0; k <= 15; ++k) p.update(w.world, w.placed, Vector3(0, 0, 0.01 - 0.001 * k), r, false);
  ASSERT_EQ(p.touches(), 1);
  EXPECT_EQ(p.substepLimited(), 0);
  const Vector3 device(0.04, 0.0, -0.005);
  const double expect_x[] = {per_cycle, 2 * per_cycle, 0.04};
  for (int cycle = 0; cycle < 3; ++cycle) {
    p.update(w.world, w.placed, device, r, false);
    EXPECT_NEAR(p.position().x(), expect_x[cycle], 1e-9) << "cycle " << cycle;
    EXPECT_NEAR(p.position().z(), r, 1e-12);
    EXPECT_EQ(p.substepLimited(), std::min(cycle + 1, 2)) << "cycle " << cycle;
  }
}

TEST(Proxy, InAnInsideCornerItStopsAndNeverEnters) {
  // The floor and a wall (x >= 0.1): the device goes deep into the corner and along it.
  SE3 wall;
  wall.p = Vector3(0.2, 0, 0.25);
  FixedWorld w({shape(CollisionShape::Kind::Plane, Vector3::Zero()), shape(CollisionShape::Kind::Box, Vector3(0.2, 1.0, 0.5), wall)});
  Proxy p(w.world);
  const Drag d = drag(w, p, Vector3(0.0, 0.0, 0.05), Vector3(0.15, 0.05, -0.05), Vector3(-1, 0, 1).normalized());
  EXPECT_GE(d.min_clearance, kRadius - 1e-9);
  EXPECT_EQ(p.touches(), 2) << "resting on the floor and the wall";
  EXPECT_NEAR(p.position().x(), 0.1 - kRadius, 1e-9);
  EXPECT_NEAR(p.position().z(), kRadius, 1e-9);
  EXPECT_NEAR(p.position().y(), 0.05, 1e-9) << "free to slide along the edge";
}

// A free body of puma_table moves into the proxy: it is carried along, on the body's surface.
TEST(Proxy, ABodyThatMovesIntoItCarriesIt) {
  const ResolvedScene r = resolveScene(loadScene(test::sourceDir() + "/scenes/puma_table.yaml"));
  Simulation sim(r);
  const GeometryModel world(*r.model, {}, {});
  GeometryData placed(world);
  Proxy p(world);
  std::vector<SE3> poses = sim.linkPoses();
  placed.place(world, poses);
  const int box = r.model->frameIndex("box_a");
  ASSERT_GE(box, 0);
  const Vector3 face = poses[static_cast<size_t>(box)].p + Vector3(0.04, 0, 0);  // box_a's +x face centre
  const Vector3 device = face + Vector3(0.015, 0, 0);  // the hand held still 1.5 cm off it
  p.update(world, placed, device, kRadius, false);
  ASSERT_FALSE(p.free());
  for (int k = 1; k <= 30; ++k) {  // the box slides +x at 1 m/s
    poses[static_cast<size_t>(box)].p.x() += 0.001;
    placed.place(world, poses);
    p.update(world, placed, device, kRadius, false);
    const PointQuery q = pointQuery(*world.object(p.touches() ? p.touch(0).geom : 0).shape,
                                    poses[static_cast<size_t>(box)], p.position());
    if (k > 5) {
      ASSERT_EQ(p.touches(), 1) << k;
      EXPECT_NEAR(q.distance, kRadius, 1e-9) << k;
      EXPECT_EQ(p.deepest(world, device, true), 0) << "a push on the box";
      EXPECT_EQ(world.object(p.touch(0).geom).frame, box);
    }
  }
  EXPECT_NEAR(p.position().x(), face.x() + 0.03 + kRadius, 1e-9);
}

TEST(Proxy, AFreeProxyEngagesOnlyAtTheSurfaceAndAJumpFreesIt) {
  FixedWorld w({shape(CollisionShape::Kind::Box, Vector3(0.2, 0.2, 0.2))});  // top face at z = 0.1
  Proxy p(w.world);
  p.update(w.world, w.placed, Vector3(0, 0, 0.09), kRadius, false);  // 2 cm deep: stays free
  EXPECT_TRUE(p.free());
  EXPECT_EQ(p.stretch(Vector3(0, 0, 0.09)), Vector3::Zero());
  p.update(w.world, w.placed, Vector3(0, 0, 0.106), kRadius, false);  // 4 mm deep: engages on the face
  EXPECT_FALSE(p.free());
  EXPECT_NEAR(p.position().z(), 0.1 + kRadius, 1e-12);
  p.update(w.world, w.placed, Vector3(0, 0, 0.08), kRadius, true);  // a pull holds: free, at the device
  EXPECT_TRUE(p.free());
  EXPECT_EQ(p.position(), Vector3(0, 0, 0.08));
  p.update(w.world, w.placed, Vector3(0, 0, 0.08), kRadius, false);  // let go inside: still free
  EXPECT_TRUE(p.free());
  p.update(w.world, w.placed, Vector3(0, 0, 0.2), kRadius, false);  // out: engages in free space
  EXPECT_FALSE(p.free());
  p.update(w.world, w.placed, Vector3(0, 0, 0.2 + 0.06), kRadius, false);  // a 6 cm jump: freed, re-engages clear
  EXPECT_FALSE(p.free());
  p.update(w.world, w.placed, Vector3(0, 0, 0.08), kRadius, false);  // a 18 cm jump into the box: free
  EXPECT_TRUE(p.free()) << "a jump does not leave the proxy on the surface with the device deep inside";
}

TEST(Proxy, AnUpdateAllocatesNothing) {
  const ResolvedScene r = resolveScene(loadScene(test::sourceDir() + "/scenes/puma_table.yaml"));
  Simulation sim(r);
  const GeometryModel& world = *r.geometry;
  GeometryData placed(world);
  Proxy p(world);
  const std::vector<SE3> poses = sim.linkPoses();
  const Vector3 top = poses[static_cast<size_t>(r.model->frameIndex("box_b"))].p + Vector3(0, 0, 0.05);
  placed.place(world, poses);
  p.update(world, placed, top, kRadius, false);
  const size_t n = test::allocationsDuring([&] {
    for (int k = 0; k < 100; ++k) {
      placed.place(world, poses);
      p.update(world, placed, top - Vector3(0, 0, 0.0005 * k), kRadius, false);
    }
  });
  EXPECT_EQ(n, 0u);
  EXPECT_GT(p.touches(), 0);
}

}  // namespace
}  // namespace igms
