// The broad phase: which of a set of axis-aligned boxes overlap, each pair once.
//   A crowd (kGrid boxes or more): a uniform grid hashed into buckets, cells as large as the largest
//     ordinary box, so that two overlapping boxes have their centres in neighbouring cells. Each box
//     is tested against the few in its 27 cells, where a sweep along one axis tested it against a
//     whole slab of the pile (150 boxes a sphere in a 10 x 10 x 10 lattice). Boxes much larger than
//     the rest (a table, a wall) and boxes whose centres are not finite are tested against every box.
//   Fewer (a robot's links, a small scene): a sweep along the axis where the boxes spread most, its
//     order kept from the last call (an insertion sort of an order that hardly changed). A robot's
//     links crowd into a few of the grid's cells, where the grid would test them all against all.
// The pairs come in no fixed order (the caller orders them). Allocation-free after construction.
#pragma once

#include <cstdint>
#include <vector>

#include "core/model/spatial.h"

namespace igms {

struct Aabb {
  Vector3 lo, hi;
};

inline bool overlap(const Aabb& a, const Aabb& b) {
  return (b.lo.array() <= a.hi.array()).all() && (a.lo.array() <= b.hi.array()).all();
}

class BroadPhase {
 public:
  static constexpr size_t kGrid = 128;  // boxes: from this many, the grid
  explicit BroadPhase(int capacity);  // the most boxes one call is given

  // Calls found(i, j) once for each overlapping pair of the boxes box[ids[k]] (i, j: entries of ids;
  // the same ids each call, as the sweep keeps their order).
  template <typename Found>
  void overlaps(const std::vector<int>& ids, const std::vector<Aabb>& box, Found&& found);

 private:
  template <typename Found>
  void sweep(const std::vector<int>& ids, const std::vector<Aabb>& box, Found&& found);

  // Sorts ids into the grid's buckets (small_) or the list of large boxes (large_). \return false:
  // no grid (too few boxes, or no box of any size).
  bool bin(const std::vector<int>& ids, const std::vector<Aabb>& box);
  size_t bucket(int64_t x, int64_t y, int64_t z) const;

  struct Cell {
    int64_t x, y, z;
  };
  std::vector<double> extent_, scratch_;  // per id: its box's largest side
  std::vector<int> small_, large_;         // ids by kind
  std::vector<Cell> cell_;                 // per small_ entry
  std::vector<int> bucket_of_;             // per small_ entry
  std::vector<int> bucket_start_;          // counting sort: per bucket, its first slot in slot_
  std::vector<int> slot_;                  // small_ entries, bucket by bucket
  std::vector<int> order_;                 // the sweep's: ids by their boxes' lower end
  size_t mask_ = 0;
};

template <typename Found>
void BroadPhase::overlaps(const std::vector<int>& ids, const std::vector<Aabb>& box, Found&& found) {
  const auto at = [&](int id) -> const Aabb& { return box[static_cast<size_t>(id)]; };
  if (!bin(ids, box)) {
    sweep(ids, box, found);
    return;
  }
  // Each small box against the boxes in its own cell that come after it in small_, and every box in
  // the 13 neighbouring cells that come after its cell (the other 13 meet it from theirs): each pair
  // once. A bucket may hold other cells' boxes too: only the cell's own are taken.
  for (size_t i = 0; i < small_.size(); ++i) {
    const Cell c = cell_[i];
    const Aabb& a = at(small_[i]);
    for (int k = 0; k < 14; ++k) {
      const int64_t dx = k < 9 ? 1 : 0, dy = k < 9 ? k / 3 - 1 : k < 12 ? 1 : 0,
                    dz = k < 9 ? k % 3 - 1 : k < 12 ? k - 10 : k == 12 ? 1 : 0;
      const Cell d{c.x + dx, c.y + dy, c.z + dz};
      const size_t b = bucket(d.x, d.y, d.z);
      for (int s = bucket_start_[b]; s < bucket_start_[b + 1]; ++s) {
        const size_t j = static_cast<size_t>(slot_[static_cast<size_t>(s)]);
        const Cell& e = cell_[j];
        if (e.x != d.x || e.y != d.y || e.z != d.z || (k == 13 && j <= i)) continue;
        if (overlap(a, at(small_[j]))) found(small_[i], small_[j]);
      }
    }
  }
  // The large boxes against every box.
  for (size_t i = 0; i < large_.size(); ++i) {
    const Aabb& a = at(large_[i]);
    for (int s : small_)
      if (overlap(a, at(s))) found(large_[i], s);
    for (size_t j = i + 1; j < large_.size(); ++j)
      if (overlap(a, at(large_[j]))) found(large_[i], large_[j]);
  }
}

template <typename Found>
void BroadPhase::sweep(const std::vector<int>& ids, const std::vector<Aabb>& box, Found&& found) {
  const auto at = [&](int id) -> const Aabb& { return box[static_cast<size_t>(id)]; };
  if (order_.size() != ids.size()) order_.assign(ids.begin(), ids.end());  // capacity reserved
  int axis = 0;
  {
    Vector3 lo = Vector3::Constant(1e300), hi = -lo;
    for (int k : order_) {
      lo = lo.cwiseMin(at(k).lo);
      hi = hi.cwiseMax(at(k).hi);
    }
    (hi - lo).maxCoeff(&axis);
  }
  for (size_t i = 1; i < order_.size(); ++i) {
    const int key = order_[i];
    const double lo = at(key).lo[axis];
    size_t j = i;
    for (; j > 0 && at(order_[j - 1]).lo[axis] > lo; --j) order_[j] = order_[j - 1];
    order_[j] = key;
  }
  for (size_t i = 0; i < order_.size(); ++i) {
    const Aabb& a = at(order_[i]);
    for (size_t j = i + 1; j < order_.size(); ++j) {
      const Aabb& b = at(order_[j]);
      if (b.lo[axis] > a.hi[axis]) break;
      if (overlap(a, b)) found(order_[i], order_[j]);
    }
  }
}

}  // namespace igms
