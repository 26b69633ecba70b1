// The broad phase (broad_phase.h) finds exactly the overlapping pairs that testing every pair finds,
// each once, on both of its paths (the sweep below BroadPhase::kGrid boxes, the grid from there):
// boxes of mixed sizes (a few very large, some far away, some not finite), a lattice whose boxes
// touch at exactly a cell's width, before and after it moves, and a handful. And it does not
// allocate once built.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <utility>

#include "core/contact/broad_phase.h"
#include "tests/support/malloc_counter.h"

namespace igms {
namespace {

using Pairs = std::set<std::pair<int, int>>;

Pairs everyPair(const std::vector<int>& ids, const std::vector<Aabb>& box) {
  Pairs out;
  for (size_t i = 0; i < ids.size(); ++i)
    for (size_t j = i + 1; j < ids.size(); ++j)
      if (overlap(box[static_cast<size_t>(ids[i])], box[static_cast<size_t>(ids[j])]))
        out.insert(std::minmax(ids[i], ids[j]));
  return out;
}

// The broad phase's pairs; fails the test on a pair met twice.
Pairs broadPhase(BroadPhase& bp, const std::vector<int>& ids, const std::vector<Aabb>& box) {
  Pairs out;
  bp.overlaps(ids, box, [&](int i, int j) {
    EXPECT_NE(i, j);
    EXPECT_TRUE(out.insert(std::minmax(i, j)).second) << "pair " << i << ", " << j << " met twice";
  });
  return out;
}

Aabb around(const Vector3& c, const Vector3& half) { return Aabb{c - half, c + half}; }

TEST(BroadPhase, FindsWhatEveryPairFindsAmongMixedSizes) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> at(-1.0, 1.0), size(0.01, 0.12), big(0.5, 3.0);
  for (int trial = 0; trial < 20; ++trial) {
    const int n = 50 + 40 * trial;
    std::vector<Aabb> box(static_cast<size_t>(n) + 3);  // three unused entries: ids need not be 0..n-1
    std::vector<int> ids;
    for (int k = 0; k < n; ++k) {
      const int id = k + (k > n / 2 ? 3 : 0);
      ids.push_back(id);
      Vector3 half(size(rng), size(rng), size(rng));
      if (k % 37 == 5) half = Vector3(big(rng), 0.02, big(rng));  // a table, a wall
      Vector3 c(at(rng), at(rng), at(rng));
      if (k % 53 == 7) c *= 1e6;                                          // far away
      if (k % 97 == 11) c.x() = std::numeric_limits<double>::quiet_NaN();  // a diverged body
      box[static_cast<size_t>(id)] = around(c, half);
    }
    std::shuffle(ids.begin(), ids.end(), rng);
    BroadPhase bp(n);
    const Pairs expected = everyPair(ids, box);
    EXPECT_EQ(broadPhase(bp, ids, box), expected) << "trial " << trial;
    if (trial == 10) EXPECT_GT(expected.size(), 400u) << "the case must be crowded to mean anything";
  }
}

TEST(BroadPhase, LatticeTouchingAtACellsWidth) {
  // Boxes of side 0.1 at 0.1 apart: every face, edge and corner neighbour touches exactly, on the
  // cells' boundaries (the grid's worst case for rounding). 4^3 boxes: the sweep; 8^3: the grid.
  for (const int side : {4, 8}) {
    std::vector<Aabb> box;
    std::vector<int> ids;
    for (int x = 0; x < side; ++x)
      for (int y = 0; y < side; ++y)
        for (int z = 0; z < side; ++z) {
          ids.push_back(static_cast<int>(box.size()));
          box.push_back(around(Vector3(0.1 * x - 0.35, 0.1 * y + 1e3, 0.1 * z), Vector3::Constant(0.05)));
        }
    BroadPhase bp(static_cast<int>(box.size()));
    const Pairs expected = everyPair(ids, box);
    EXPECT_GE(expected.size(), 3u * (side - 1) * side * side) << "at least the face neighbours";
    EXPECT_EQ(broadPhase(bp, ids, box), expected) << side;
    // Moved (the sweep's kept order is now out of date): the same pairs as every pair finds.
    for (Aabb& b : box) b.lo.x() = -b.lo.x(), b.hi.x() = -b.hi.x(), std::swap(b.lo.x(), b.hi.x());
    EXPECT_EQ(broadPhase(bp, ids, box), everyPair(ids, box)) << side << ", mirrored";
  }
}

TEST(BroadPhase, AFewBoxesAndNone) {
  std::vector<Aabb> box{around(Vector3::Zero(), Vector3::Constant(1.0)), around(Vector3(1.5, 0, 0), Vector3::Constant(1.0)),
                        around(Vector3(5, 0, 0), Vector3::Constant(1.0))};
  BroadPhase bp(3);
  EXPECT_EQ(broadPhase(bp, {0, 1, 2}, box), (Pairs{{0, 1}}));
  EXPECT_TRUE(broadPhase(bp, {}, box).empty());
}

TEST(BroadPhase, AllocatesNothingOnceBuilt) {
  std::vector<Aabb> box;
  std::vector<int> ids;
  for (int k = 0; k < 500; ++k) {
    ids.push_back(k);
    box.push_back(around(Vector3(0.1 * (k % 10), 0.1 * ((k / 10) % 10), 0.1 * (k / 100)), Vector3::Constant(0.06)));
  }
  BroadPhase bp(500);
  int found = 0;
  bp.overlaps(ids, box, [&](int, int) { ++found; });
  found = 0;
  EXPECT_EQ(test::allocationsDuring([&] { bp.overlaps(ids, box, [&](int, int) { ++found; }); }), 0u);
  EXPECT_EQ(found, static_cast<int>(everyPair(ids, box).size()));
}

}  // namespace
}  // namespace igms
