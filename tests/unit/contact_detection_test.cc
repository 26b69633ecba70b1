// Contact detection (contact_detection.h) keeps a list of the pairs near each other between broad
// phases (a Verlet list). Whatever the bodies do (creep, turn a long stick whose box changes as it
// turns, jump across the scene, leave the finite), every step's contacts must be exactly those that
// shapeContacts gives over every pair that may touch: the same pairs, points, normals and gaps, bit
// for bit, in the same order. Checked with the grid (from BroadPhase::kGrid geoms) and the sweep
// behind the list; and the list must actually serve (a broad phase every step would pass the
// comparison and prove nothing), and it allocates nothing, rebuilt or not.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "core/contact/contact_detection.h"
#include "core/geometry/shape_contact.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/model/configuration.h"
#include "core/scene/scene.h"
#include "core/simulation/simulation.h"
#include "tests/support/malloc_counter.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

// Free bodies of every primitive kind, long sticks among them, packed in a 0.6 m cube over the
// ground beside a fixed table.
std::string crowd(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> at(-0.3, 0.3), size(0.02, 0.06);
  std::ostringstream s;
  s << "ground: {height: 0}\n"
    << "obstacles:\n  - {name: table, shape: box, size: [0.4, 0.4, 0.04], xyz: [0.5, 0, 0.3], solid: true}\n"
    << "bodies:\n";
  for (int k = 0; k < n; ++k) {
    s << "  - {name: b" << k << ", mass: 1, xyz: [" << at(rng) << ", " << at(rng) << ", " << 0.35 + at(rng)
      << "], rpy: [" << at(rng) * 5 << ", " << at(rng) * 5 << ", " << at(rng) * 5 << "], ";
    switch (k % 5) {
      case 0: s << "shape: sphere, radius: " << size(rng); break;
      case 1: s << "shape: box, size: [" << size(rng) << ", " << size(rng) << ", " << size(rng) << "]"; break;
      case 2: s << "shape: box, size: [0.5, 0.02, 0.02]"; break;  // a stick: its box changes as it turns
      case 3: s << "shape: capsule, radius: " << size(rng) << ", length: " << 2 * size(rng); break;
      default: s << "shape: cylinder, radius: " << size(rng) << ", length: " << 2 * size(rng); break;
    }
    s << "}\n";
  }
  s << "contact: {margin: 0.005}\n";
  return s.str();
}

struct Found {
  int a, b;
  Vector3 point, normal;
  double distance;
};

// shapeContacts over every pair that may touch, in order by pair (the frames' poses from forward
// kinematics, data.oMf).
std::vector<Found> everyPair(const ContactModel& cm, const Data& data) {
  const auto& geoms = cm.geometry().objects();
  std::vector<SE3> pose(geoms.size());
  for (size_t k = 0; k < geoms.size(); ++k)
    pose[k] = geoms[k].frame < 0 ? geoms[k].placement : data.oMf[static_cast<size_t>(geoms[k].frame)] * geoms[k].placement;
  std::vector<Found> out;
  ContactPoint pts[kMaxPairPoints];
  for (size_t i = 0; i < geoms.size(); ++i)
    for (size_t j = i + 1; j < geoms.size(); ++j) {
      if (!cm.canTouch(static_cast<int>(i), static_cast<int>(j))) continue;
      const int n = shapeContacts(*geoms[i].shape, pose[i], *geoms[j].shape, pose[j], cm.settings().margin, pts);
      for (int s = 0; s < n; ++s)
        out.push_back({static_cast<int>(i), static_cast<int>(j), pts[s].point, pts[s].normal, pts[s].distance});
    }
  return out;
}

// A scene, and a detection of its own with its data and contact set.
struct Detecting {
  explicit Detecting(const std::string& yaml)
      : sim(parseScene(yaml, "test.yaml", test::sourceDir() + "/scenes")),
        model(sim.model()),
        cm(*sim.contactModel()),
        data(model),
        detection(cm),
        set(cm.capacity()) {}
  // The contacts at q.
  void detectAt(const VectorX& q) {
    forwardKinematics(model, data, q);
    placed.place(sim.geometry(), model, data);
    detection.detect(placed, set);
  }
  Simulation sim;
  const Model& model;
  const ContactModel& cm;
  Data data;
  GeometryData placed{sim.geometry()};
  ContactDetection detection;
  ContactSet set;
};

// Steps the crowd through creeping, turning and jumping, comparing the detection with every pair.
// \return the steps compared.
int compareThroughMotion(int bodies, unsigned seed) {
  Detecting d(crowd(bodies, seed));
  const Model& model = d.model;
  std::mt19937 rng(seed + 1);
  std::normal_distribution<double> creep(0.0, 0.3), jump(0.0, 300.0);
  std::uniform_int_distribution<int> pick(0, model.nv / 6 - 1);
  VectorX q = d.sim.q(), v(model.nv);
  const double h = 1e-3;
  int compared = 0;
  size_t allocations = 0;  // in the detection, its list's rebuilds included
  for (int step = 0; step < 400; ++step) {
    // Creep: up to a few mm a step, the sticks turning at a few rad/s (their ends sweep the most).
    for (int k = 0; k < model.nv; ++k) v[k] = (k % 6 < 3 ? 1.0 : 10.0) * creep(rng);
    if (step % 40 == 39) v.segment<3>(6 * pick(rng)) = Vector3(jump(rng), jump(rng), jump(rng));  // a jump
    if (step % 100 == 70) v.setZero();  // still: the list must hold while nothing moves
    integrateConfiguration(model, q, v, h, q);
    allocations += test::allocationsDuring([&] { d.detectAt(q); });
    const std::vector<Found> want = everyPair(d.cm, d.data);
    const ContactSet& set = d.set;
    EXPECT_EQ(set.n, static_cast<int>(want.size())) << "step " << step;
    if (set.n != static_cast<int>(want.size())) return compared;
    for (int k = 0; k < set.n; ++k) {
      const Contact& c = set[k];
      const Found& w = want[static_cast<size_t>(k)];
      const bool same = c.geom_a == w.a && c.geom_b == w.b && c.point == w.point && c.normal == w.normal &&
                        c.distance == w.distance;
      EXPECT_TRUE(same) << "step " << step << ", contact " << k << ": " << c.geom_a << "-" << c.geom_b
                        << " against " << w.a << "-" << w.b;
      if (!same) return compared;
    }
    ++compared;
  }
  // A body leaves the finite (a diverged step): no crash, and once it is back the contacts agree.
  VectorX bad = q;
  bad[0] = std::numeric_limits<double>::quiet_NaN();
  d.detectAt(bad);
  d.detectAt(q);
  EXPECT_EQ(d.set.n, static_cast<int>(everyPair(d.cm, d.data).size()));
  EXPECT_EQ(allocations, 0u);
  EXPECT_GT(d.detection.nearRebuilds(), 4) << "the bodies moved past the skin: the list was rebuilt";
  EXPECT_LT(d.detection.nearRebuilds(), compared / 3) << "the list served between rebuilds";
  return compared;
}

TEST(ContactDetection, TheNearListFindsWhatEveryPairFindsInACrowd) {
  // 150 bodies and the table: the broad phase behind the list is the grid.
  EXPECT_EQ(compareThroughMotion(150, 3), 400);
}

TEST(ContactDetection, TheNearListFindsWhatEveryPairFindsAmongAFew) {
  // 30 bodies: the sweep behind the list.
  EXPECT_EQ(compareThroughMotion(30, 11), 400);
}

TEST(ContactDetection, TwoBodiesClosingFromBothSidesAreFound) {
  // Two balls beyond margin + skin close on each other, each by less than the skin: the list must
  // count both moves (a list that checked each body's move alone would miss them).
  Detecting d(
      "bodies:\n"
      "  - {name: a, shape: sphere, radius: 0.05, mass: 1, xyz: [0, 0, 1]}\n"
      "  - {name: b, shape: sphere, radius: 0.05, mass: 1, xyz: [0.2, 0, 1]}\n"
      "contact: {margin: 0.005}\n");
  const Model& model = d.model;
  const double margin = 0.005, skin = d.detection.skin(), start = margin + skin + 1e-3;
  ASSERT_GE(skin, margin);
  const VectorX q0 = d.sim.q();  // 0.1 m apart
  VectorX q = q0;
  auto place = [&](double gap) {  // each ball moved half the way along x
    const double moved = 0.5 * (0.1 - gap);
    q[model.q_index[0]] = q0[model.q_index[0]] + moved;
    q[model.q_index[1]] = q0[model.q_index[1]] - moved;
  };
  int rebuilds = -1;
  for (double gap = start; gap > 0.5 * margin; gap -= 2e-4) {
    place(gap);
    d.detectAt(q);
    if (rebuilds < 0) rebuilds = static_cast<int>(d.detection.nearRebuilds());
    ASSERT_EQ(d.set.n, gap < margin ? 1 : 0) << "gap " << gap;
    if (d.set.n == 1) {
      EXPECT_NEAR(d.set[0].distance, gap, 1e-12);
    }
  }
  EXPECT_EQ(d.detection.nearRebuilds(), rebuilds + 1) << "one rebuild, once they had moved the skin between them";
}

TEST(ContactDetection, AStickTurningInPlaceIsFound) {
  // A 0.5 m stick turns about its centre, which stays put, into a ball beside it: its box grows as it
  // turns, its bounding sphere does not (a list built from the boxes it had would miss the ball).
  Detecting d(
      "bodies:\n"
      "  - {name: stick, shape: box, size: [0.5, 0.02, 0.02], mass: 1, xyz: [0, 0, 1]}\n"
      "  - {name: ball, shape: sphere, radius: 0.05, mass: 1, xyz: [0.2, 0.12, 1]}\n"
      "contact: {margin: 0.005}\n");
  const Model& model = d.model;
  VectorX q = d.sim.q(), v = VectorX::Zero(model.nv);
  v[5] = 2.0;  // the stick's spin about z (its body axes: the last three of its six)
  int touching = 0;
  for (int step = 0; step < 400; ++step) {
    integrateConfiguration(model, q, v, 1e-3, q);
    d.detectAt(q);
    ASSERT_EQ(d.set.n, static_cast<int>(everyPair(d.cm, d.data).size())) << "step " << step;
    touching += d.set.n > 0;
  }
  EXPECT_GT(touching, 0) << "the stick reached the ball";
  EXPECT_EQ(d.detection.nearRebuilds(), 1) << "its centre never moved";
}

TEST(ContactDetection, ACrowdTooDenseForTheListFallsBackAndCountsWhatItDrops) {
  // 60 balls heaped on one spot: 1770 overlapping pairs, more than the buffers hold (16 a geom). The
  // list cannot be built: each step takes the broad phase straight and counts the pairs it drops.
  // Spread out, the list serves again and the contacts are every pair's.
  std::ostringstream yaml;
  yaml << "bodies:\n";
  for (int k = 0; k < 60; ++k)
    yaml << "  - {name: b" << k << ", shape: sphere, radius: 0.05, mass: 1, xyz: [" << 1e-4 * k << ", 0, 1]}\n";
  Detecting d(yaml.str());
  VectorX q = d.sim.q();
  int64_t rebuilds = 0;
  for (int step = 0; step < 5; ++step) {
    const size_t allocations = test::allocationsDuring([&] { d.detectAt(q); });
    EXPECT_EQ(allocations, 0u);
    EXPECT_GT(d.set.n, 0);
    EXPECT_EQ(d.detection.nearRebuilds(), ++rebuilds) << "no list to keep: the broad phase every step";
  }
  EXPECT_GT(d.detection.candidatePairsDropped(), 0);
  for (int k = 0; k < 60; ++k) q[d.model.q_index[k] + 1] = 0.0999 * k;  // in a row, neighbours 0.1 mm apart
  for (int step = 0; step < 3; ++step) {
    d.detectAt(q);
    EXPECT_EQ(d.set.n, static_cast<int>(everyPair(d.cm, d.data).size()));
    EXPECT_EQ(d.set.n, 59);
  }
  EXPECT_EQ(d.detection.nearRebuilds(), rebuilds + 1) << "spread out, one list serves";
}

}  // namespace
}  // namespace igms
