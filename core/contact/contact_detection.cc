#include "core/contact/contact_detection.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/shape_contact.h"

namespace igms {

ContactDetection::ContactDetection(const ContactModel& model)
    : cm_(model), broad_phase_(model.size()) {
  const auto& g = cm_.geometry().objects();
  box_.resize(g.size());
  wide_.resize(g.size());
  centre_.resize(g.size());
  built_centre_.resize(g.size());
  reach_.resize(g.size());
  for (size_t k = 0; k < g.size(); ++k) {
    reach_[k] = g[k].radius;
    if (!g[k].collides) continue;  // a ghost, a mesh without samples
    if (g[k].plane) planes_.push_back(static_cast<int>(k));
    else solids_.push_back(static_cast<int>(k));
    if (g[k].body >= 0 && !g[k].plane) moving_.push_back(static_cast<int>(k));
  }
  // Candidates: a few per geom, as many as contact points can be held.
  pairs_.resize(static_cast<size_t>(std::max(cm_.capacity(), 16 * static_cast<int>(g.size()) + 64)));
  sorted_.resize(pairs_.size());
  near_.resize(pairs_.size());
  planar_.resize(pairs_.size());
  first_count_.resize(g.size() + 1);
  // The skin: a tenth of the median geom's bounding radius (5 mm for a pile of 5 cm balls), and no
  // less than the margin. Larger, the list holds longer while things move and costs more each step.
  std::vector<double> reach;
  for (int k : solids_) reach.push_back(reach_[static_cast<size_t>(k)]);
  std::sort(reach.begin(), reach.end());
  const double median = reach.empty() ? 0.0 : reach[reach.size() / 2];
  skin_ = std::max(cm_.settings().margin, std::isfinite(median) ? 0.1 * median : 0.0);
}

void ContactDetection::place(const GeometryData& placed) {
  pose_ = placed.oMg.data();
  const double margin = cm_.settings().margin;
  for (int k : solids_) {
    const GeometryObject& g = cm_.geom(k);
    const Matrix3& R = pose_[k].R;
    const Vector3 centre = pose_[k].act(g.box_centre);
    const Vector3 half = R.cwiseAbs() * g.box_half + Vector3::Constant(0.5 * margin);
    box_[k] = Aabb{centre - half, centre + half};
    centre_[k] = centre;
  }
}

int ContactDetection::findPairs(const std::vector<Aabb>& boxes, double extra, std::vector<std::pair<int, int>>& out,
                                int& n) {
  n = 0;
  int dropped = 0;
  // Boxes of round shapes overlap where the shapes are far apart (a lattice's diagonal neighbours):
  // their bounding spheres too.
  broad_phase_.overlaps(solids_, boxes, [&](int i, int j) {
    const double reach = reach_[static_cast<size_t>(i)] + reach_[static_cast<size_t>(j)] + extra;
    if (!((centre_[static_cast<size_t>(i)] - centre_[static_cast<size_t>(j)]).squaredNorm() < reach * reach)) return;
    if (i > j) std::swap(i, j);
    if (!cm_.canTouch(i, j)) return;
    if (n >= static_cast<int>(out.size())) {
      ++dropped;
      return;
    }
    out[static_cast<size_t>(n++)] = {i, j};
  });
  // A fixed order: by pair. Counting sort on the first geom (the broad phase leaves them in any
  // order), then each first geom's few partners by insertion: linear in the pairs, where a comparison
  // sort of a crowded scene's thousands of pairs was a fifth of its detection.
  std::fill(first_count_.begin(), first_count_.end(), 0);
  for (int k = 0; k < n; ++k) ++first_count_[static_cast<size_t>(out[static_cast<size_t>(k)].first) + 1];
  for (size_t g = 1; g < first_count_.size(); ++g) first_count_[g] += first_count_[g - 1];
  for (int k = 0; k < n; ++k) {
    const auto& p = out[static_cast<size_t>(k)];
    sorted_[static_cast<size_t>(first_count_[static_cast<size_t>(p.first)]++)] = p;
  }
  std::copy(sorted_.begin(), sorted_.begin() + n, out.begin());
  for (int k = 1; k < n; ++k)  // equal first geoms are adjacent now: order their seconds
    for (int j = k; j > 0 && out[static_cast<size_t>(j - 1)] > out[static_cast<size_t>(j)]; --j)
      std::swap(out[static_cast<size_t>(j - 1)], out[static_cast<size_t>(j)]);
  return dropped;
}

bool ContactDetection::nearListHolds() const {
  // A pair the list left out was farther apart than margin + skin when it was built; to come within
  // the margin now, its two geoms must have moved more than the skin between them.
  double first = 0.0, second = 0.0;  // the two largest squared displacements
  for (int k : solids_) {
    const double d2 = (centre_[static_cast<size_t>(k)] - built_centre_[static_cast<size_t>(k)]).squaredNorm();
    if (!(d2 <= skin_ * skin_)) return false;  // also not finite
    if (d2 > first) {
      second = first;
      first = d2;
    } else if (d2 > second) {
      second = d2;
    }
  }
  return std::sqrt(first) + std::sqrt(second) <= skin_;
}

void ContactDetection::detect(const GeometryData& placed, ContactSet& out) {
  place(placed);
  broadPhase();
  planeCandidates();
  narrowPhase(out);
}

void ContactDetection::broadPhase() {
  const double margin = cm_.settings().margin;
  if (!near_valid_ || !nearListHolds()) {
    // The pairs whose bounding spheres come within margin + skin, found through boxes that hold
    // those spheres (a box's own bounds change as it turns; its sphere's do not).
    ++rebuilds_;
    const double grow = 0.5 * (margin + skin_);
    for (int k : solids_) {
      const size_t K = static_cast<size_t>(k);
      wide_[K] = Aabb{centre_[K] - Vector3::Constant(reach_[K] + grow), centre_[K] + Vector3::Constant(reach_[K] + grow)};
      built_centre_[K] = centre_[K];
    }
    near_valid_ = findPairs(wide_, margin + skin_, near_, nnear_) == 0;
  }
  if (!near_valid_) {
    // Too many near pairs for the list: this step's candidates straight from the broad phase.
    pairs_dropped_ += findPairs(box_, margin, pairs_, npairs_);
    return;
  }
  // The list's pairs that are candidates now, in its order (by pair).
  npairs_ = 0;
  for (int k = 0; k < nnear_; ++k) {
    const auto [i, j] = near_[static_cast<size_t>(k)];
    const size_t I = static_cast<size_t>(i), J = static_cast<size_t>(j);
    const double reach = reach_[I] + reach_[J] + margin;
    if (!overlap(box_[I], box_[J]) || !((centre_[I] - centre_[J]).squaredNorm() < reach * reach)) continue;
    if (npairs_ >= static_cast<int>(pairs_.size())) {
      ++pairs_dropped_;
      continue;
    }
    pairs_[static_cast<size_t>(npairs_++)] = near_[static_cast<size_t>(k)];
  }
}

void ContactDetection::planeCandidates() {
  // Planes against every moving geom whose box reaches below them; merged into the order by pair
  // (one plane's pairs come in order already).
  const double margin = cm_.settings().margin;
  int nplanar = 0;
  for (int p : planes_) {
    const Vector3 n = pose_[p].R.col(2);
    const double offset = n.dot(pose_[p].p);
    for (int k : moving_) {
      const Aabb& b = box_[static_cast<size_t>(k)];
      const Vector3 centre = 0.5 * (b.lo + b.hi), half = 0.5 * (b.hi - b.lo);
      if (!(n.dot(centre) - n.cwiseAbs().dot(half) - offset < 0.5 * margin)) continue;
      const std::pair<int, int> pair = std::minmax(p, k);
      if (!cm_.canTouch(pair.first, pair.second)) continue;
      if (nplanar + npairs_ >= static_cast<int>(pairs_.size())) {
        ++pairs_dropped_;
        continue;
      }
      planar_[static_cast<size_t>(nplanar++)] = pair;
    }
  }
  if (nplanar == 0) return;
  if (planes_.size() > 1) std::sort(planar_.begin(), planar_.begin() + nplanar);
  std::merge(pairs_.begin(), pairs_.begin() + npairs_, planar_.begin(), planar_.begin() + nplanar, sorted_.begin());
  std::swap(pairs_, sorted_);
  npairs_ += nplanar;
}

void ContactDetection::narrowPhase(ContactSet& out) const {
  const double margin = cm_.settings().margin;
  out.n = 0;
  ContactPoint pts[kMaxPairPoints];
  for (int k = 0; k < npairs_; ++k) {
    const auto [i, j] = pairs_[static_cast<size_t>(k)];
    const GeometryObject &a = cm_.geom(i), &b = cm_.geom(j);
    const int n = shapeContacts(*a.shape, pose_[i], *b.shape, pose_[j], margin, pts);
    if (n == 0) continue;
    const Material m = combine(cm_.material(a.material), cm_.material(b.material));
    for (int s = 0; s < n; ++s) {
      if (out.n >= out.capacity()) {
        ++out.dropped;
        continue;
      }
      Contact& c = out[out.n++];
      c.geom_a = i;
      c.geom_b = j;
      c.body_a = a.body;
      c.body_b = b.body;
      c.slot = s;
      c.point = pts[s].point;
      c.normal = pts[s].normal;
      c.distance = pts[s].distance;
      c.friction = m.friction;
      c.rolling = m.rolling;
      c.torsion = m.torsion;
      c.restitution = m.restitution;
      c.impulse.setZero();
      c.moment.setZero();
    }
  }
}

}  // namespace igms
