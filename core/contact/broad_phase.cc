#include "core/contact/broad_phase.h"

#include <algorithm>
#include <cmath>

namespace igms {

namespace {

constexpr double kLarge = 4.0;         // a box this many times the median's side is tested against all
constexpr double kFarthest = 1e15;     // cells: a centre beyond this many is tested against all

}  // namespace

BroadPhase::BroadPhase(int capacity) {
  const size_t n = static_cast<size_t>(std::max(capacity, 1));
  extent_.resize(n);
  scratch_.resize(n);
  small_.reserve(n);
  large_.reserve(n);
  cell_.resize(n);
  bucket_of_.resize(n);
  slot_.resize(n);
  order_.reserve(n);
  size_t buckets = 1;
  while (buckets < 2 * n) buckets *= 2;
  bucket_start_.resize(buckets + 1);
  mask_ = buckets - 1;
}

size_t BroadPhase::bucket(int64_t x, int64_t y, int64_t z) const {
  const uint64_t h = static_cast<uint64_t>(x) * 73856093u ^ static_cast<uint64_t>(y) * 19349663u ^
                     static_cast<uint64_t>(z) * 83492791u;
  return static_cast<size_t>(h ^ (h >> 29)) & mask_;
}

bool BroadPhase::bin(const std::vector<int>& ids, const std::vector<Aabb>& box) {
  const size_t n = ids.size();
  small_.clear();
  large_.clear();
  if (n < kGrid || n > extent_.size()) return false;
  for (size_t k = 0; k < n; ++k) {
    const Aabb& b = box[static_cast<size_t>(ids[k])];
    extent_[k] = (b.hi - b.lo).maxCoeff();
    scratch_[k] = std::isfinite(extent_[k]) ? extent_[k] : 0.0;
  }
  std::nth_element(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(n / 2),
                   scratch_.begin() + static_cast<std::ptrdiff_t>(n));
  const double median = scratch_[n / 2];
  if (!(median > 0.0)) return false;
  // The cell: the largest ordinary box's side, a little more so that two boxes that overlap at
  // exactly a cell's width apart still land in neighbouring cells after rounding.
  double side = 0.0;
  for (size_t k = 0; k < n; ++k)
    if (extent_[k] <= kLarge * median) side = std::max(side, extent_[k]);
  side *= 1.0 + 1e-9;
  const double inv = 1.0 / side;
  for (size_t k = 0; k < n; ++k) {
    const Aabb& b = box[static_cast<size_t>(ids[k])];
    const Vector3 c = 0.5 * (b.lo + b.hi) * inv;
    if (!(extent_[k] <= kLarge * median) || !(c.cwiseAbs().maxCoeff() < kFarthest)) {  // also NaN
      large_.push_back(ids[k]);
      continue;
    }
    const size_t s = small_.size();
    small_.push_back(ids[k]);
    cell_[s] = Cell{static_cast<int64_t>(std::floor(c.x())), static_cast<int64_t>(std::floor(c.y())),
                    static_cast<int64_t>(std::floor(c.z()))};
    bucket_of_[s] = static_cast<int>(bucket(cell_[s].x, cell_[s].y, cell_[s].z));
  }
  // Counting sort of the small boxes by bucket (in small_'s order within each).
  std::fill(bucket_start_.begin(), bucket_start_.end(), 0);
  for (size_t s = 0; s < small_.size(); ++s) ++bucket_start_[static_cast<size_t>(bucket_of_[s]) + 1];
  for (size_t b = 1; b < bucket_start_.size(); ++b) bucket_start_[b] += bucket_start_[b - 1];
  for (size_t s = 0; s < small_.size(); ++s) slot_[static_cast<size_t>(bucket_start_[static_cast<size_t>(bucket_of_[s])]++)] = static_cast<int>(s);
  // The sort advanced each bucket's start to its end: step them back.
  for (size_t b = bucket_start_.size() - 1; b > 0; --b) bucket_start_[b] = bucket_start_[b - 1];
  bucket_start_[0] = 0;
  return true;
}

}  // namespace igms
