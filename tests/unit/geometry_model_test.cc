// The geometry world (core/geometry/geometry_model.h): one list of shapes that
// the contact layer, the hands' proxies and the obstacle monitor all index
// into, placed by one formula whichever poses a caller has.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <random>

#include "core/kinematics/forward_kinematics.h"
#include "core/model/configuration.h"
#include "core/simulation/simulation.h"
#include "server/collision/collision_world.h"
#include "tests/support/malloc_counter.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

Scene shipped(const char* name) { return loadScene(test::sourceDir() + "/scenes/" + name); }

bool sameBits(const SE3& a, const SE3& b) {
  return std::memcmp(a.R.data(), b.R.data(), sizeof(double) * 9) == 0 &&
         std::memcmp(a.p.data(), b.p.data(), sizeof(double) * 3) == 0;
}

// A random configuration of the whole environment (normalised where it must be).
VectorX anyConfiguration(const Model& m, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  VectorX q = neutralConfiguration(m);
  for (int k = 0; k < m.nq; ++k) q[k] += 0.5 * u(rng);
  normalizeConfiguration(m, q);
  return q;
}

// At any configuration, placing from the bodies (the server's step) and from every frame's pose (a
// client's estimate, the obstacle monitor) gives the same bits, and that is the frame's pose as
// forward kinematics gives it times the shape's placement.
TEST(GeometryModel, PlacedFromBodiesOrFromFramesTheSameBits) {
  std::vector<std::string> scenes = {"puma_table.yaml", "go1_stand.yaml", "workcell.yaml", "sphere_pile.yaml"};
  if (std::filesystem::exists(test::sourceDir() + "/third_party/example-robot-data/robots/talos_data"))
    scenes.push_back("talos_stand.yaml");
  std::mt19937 rng(3);
  int off_body = 0;  // shapes on a frame that is not its body's own (a fixed joint's link)
  for (const std::string& name : scenes) {
    const ResolvedScene r = resolveScene(shipped(name.c_str()));
    const Model& m = *r.model;
    const GeometryModel& g = *r.geometry;
    Data data(m);
    GeometryData from_bodies(g), from_frames(g);
    for (int trial = 0; trial < 5; ++trial) {
      forwardKinematics(m, data, anyConfiguration(m, rng));
      from_bodies.place(g, m, data);
      from_frames.place(g, data.oMf);
      for (int k = 0; k < g.size(); ++k) {
        const GeometryObject& o = g.object(k);
        const SE3 expected = o.frame < 0 ? o.placement : data.oMf[static_cast<size_t>(o.frame)] * o.placement;
        EXPECT_TRUE(sameBits(from_bodies.oMg[static_cast<size_t>(k)], expected)) << name << ": " << o.name;
        EXPECT_TRUE(sameBits(from_frames.oMg[static_cast<size_t>(k)], expected)) << name << ": " << o.name;
        if (trial == 0 && o.body >= 0 && !o.frame_is_body) ++off_body;
      }
    }
  }
  EXPECT_GT(off_body, 0) << "no shape on a fixed joint's link: the path that composes the frame's placement is untested";
}

// puma_table: the PUMA's links, the three boxes, then the scene's own in its order (the wall a ghost,
// the table solid), then the ground; what each user may touch.
TEST(GeometryModel, OneListInModelThenSceneOrderWithWhatEachUserTakes) {
  const ResolvedScene r = resolveScene(shipped("puma_table.yaml"));
  const GeometryModel& g = *r.geometry;
  const Model& m = *r.model;
  ASSERT_GE(g.size(), 6);
  const int n = g.size();
  const GeometryObject &wall = g.object(n - 3), &table = g.object(n - 2), &ground = g.object(n - 1);
  EXPECT_EQ(wall.name, "wall");
  EXPECT_EQ(table.name, "table");
  EXPECT_EQ(ground.name, "ground");
  EXPECT_FALSE(wall.solid);
  EXPECT_FALSE(wall.collides);
  EXPECT_FALSE(wall.touchable);
  EXPECT_TRUE(wall.has_volume) << "the monitor watches it";
  EXPECT_TRUE(table.collides && table.touchable && table.has_volume);
  EXPECT_TRUE(ground.plane && ground.collides && ground.touchable);
  EXPECT_FALSE(ground.has_volume) << "FCL does not take the ground";
  EXPECT_EQ(table.material, r.materialIndex("wood"));
  EXPECT_EQ(ground.material, r.materialIndex("floor"));
  for (int k = 0; k < n - 3; ++k) {  // the model's shapes, frame by frame
    const GeometryObject& o = g.object(k);
    ASSERT_GE(o.frame, 0);
    if (k > 0) {
      EXPECT_GE(o.frame, g.object(k - 1).frame);
    }
    EXPECT_EQ(o.body, m.frame(o.frame).body);
    EXPECT_EQ(o.part, m.partOfFrame(o.frame));
    EXPECT_EQ(o.name, m.frame(o.frame).name);
  }
  const int box_a = m.frameIndex("box_a");
  for (int k = 0; k < n; ++k) {
    if (g.object(k).frame == box_a) {
      EXPECT_EQ(g.object(k).material, r.materialIndex("wood"));
    }
  }
}

// The contact layer, the step's proxy and the obstacle monitor name the same objects: a contact's geoms
// are on its bodies, the proxy's touch is the box it pushes, the monitor's nearest is the wall.
TEST(GeometryModel, ContactProxyAndMonitorIndexTheSameObjects) {
  Simulation sim(resolveScene(shipped("puma_table.yaml")));
  const GeometryModel& g = sim.geometry();
  const Model& m = sim.model();
  for (int k = 0; k < 200; ++k) sim.step(nullptr);  // the boxes settle on the table
  const ContactSet& set = sim.contacts();
  ASSERT_GT(set.n, 0);
  for (int k = 0; k < set.n; ++k) {
    EXPECT_EQ(g.object(set[k].geom_a).body, set[k].body_a);
    EXPECT_EQ(g.object(set[k].geom_b).body, set[k].body_b);
    EXPECT_TRUE(g.object(set[k].geom_a).collides && g.object(set[k].geom_b).collides);
  }
  // A hand pushing box_b from above: the proxy rests on box_b's top face.
  const int box_b = m.frameIndex("box_b");
  const Vector3 top = sim.linkPoses()[static_cast<size_t>(box_b)].p + Vector3(0, 0, 0.04);
  InteractionInput in;
  in.client = 1;
  in.mode = InteractionMode::Push;
  in.tip_radius = sim.scene().push.tip_radius;
  for (int k = 0; k < 20; ++k) {
    in.seq = k;
    in.tip_position = top + Vector3(0, 0, in.tip_radius + 0.01 - 0.001 * k);
    sim.step(&in);
  }
  const Proxy* proxy = sim.proxyOf(1);
  ASSERT_NE(proxy, nullptr);
  ASSERT_GT(proxy->touches(), 0);
  EXPECT_EQ(g.object(proxy->touch(0).geom).frame, box_b);
  CollisionWorld monitor(m, g);
  ASSERT_FALSE(monitor.empty());
  const CollisionReport c = monitor.check(sim.linkPoses());
  EXPECT_EQ(c.closest_obstacle, "wall") << "the table is solid: touched through contact, not watched";
  EXPECT_GT(c.min_distance, 0.0);
}

TEST(GeometryModel, PlacingAllocatesNothing) {
  const ResolvedScene r = resolveScene(shipped("workcell.yaml"));
  const Model& m = *r.model;
  Data data(m);
  GeometryData placed(*r.geometry);
  bodyKinematics(m, data, r.q0);
  const size_t n = test::allocationsDuring([&] {
    for (int k = 0; k < 10; ++k) placed.place(*r.geometry, m, data);
  });
  EXPECT_EQ(n, 0u);
}

}  // namespace
}  // namespace igms
