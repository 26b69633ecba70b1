#include "core/contact/contact_detection.h"

#include <algorithm>

#include "core/geometry/shape_bounds.h"
#include "core/geometry/shape_contact.h"

namespace igms {

ContactDetection::ContactDetection(const ContactModel& model)
    : cm_(model), broad_phase_(static_cast<int>(model.geoms().size())) {
  const auto& g = cm_.geoms();
  pose_.resize(g.size());
  box_.resize(g.size());
  centre_.resize(g.size());
  reach_.resize(g.size());
  for (size_t k = 0; k < g.size(); ++k) {
    reach_[k] = boundingRadius(*g[k].shape);
    if (g[k].plane) planes_.push_back(static_cast<int>(k));
    else solids_.push_back(static_cast<int>(k));
    if (g[k].body >= 0 && !g[k].plane) moving_.push_back(static_cast<int>(k));
  }
  // Candidates: a few per geom, as many as contact points can be held.
  pairs_.resize(static_cast<size_t>(std::max(cm_.capacity(), 16 * static_cast<int>(g.size()) + 64)));
  sorted_.resize(pairs_.size());
  first_count_.resize(g.size() + 1);
}

void ContactDetection::detect(const Data& data, ContactSet& out) {
  const auto& geoms = cm_.geoms();
  const double margin = cm_.settings().margin;
  // World poses and boxes.
  for (size_t k = 0; k < geoms.size(); ++k) {
    const Geom& g = geoms[k];
    pose_[k] = g.body < 0 ? g.placement : data.oMi[static_cast<size_t>(g.body)] * g.placement;
    if (g.plane) continue;
    const Matrix3& R = pose_[k].R;
    const Vector3 centre = pose_[k].act(g.box_centre);
    const Vector3 half = R.cwiseAbs() * g.box_half + Vector3::Constant(0.5 * margin);
    box_[k] = Aabb{centre - half, centre + half};
    centre_[k] = centre;
  }
  npairs_ = 0;
  auto candidate = [&](int i, int j) {
    if (i > j) std::swap(i, j);
    if (!cm_.canTouch(i, j)) return;
    if (npairs_ >= static_cast<int>(pairs_.size())) {
      ++pairs_dropped_;
      return;
    }
    pairs_[static_cast<size_t>(npairs_++)] = {i, j};
  };
  // Boxes of round shapes overlap where the shapes are far apart (a lattice's diagonal neighbours):
  // their bounding spheres too.
  broad_phase_.overlaps(solids_, box_, [&](int i, int j) {
    const double reach = reach_[static_cast<size_t>(i)] + reach_[static_cast<size_t>(j)] + margin;
    if ((centre_[static_cast<size_t>(i)] - centre_[static_cast<size_t>(j)]).squaredNorm() < reach * reach) candidate(i, j);
  });
  // Planes against every moving geom whose box reaches below them.
  for (int p : planes_) {
    const Vector3 n = pose_[static_cast<size_t>(p)].R.col(2);
    const double offset = n.dot(pose_[static_cast<size_t>(p)].p);
    for (int k : moving_) {
      const Aabb& b = box_[static_cast<size_t>(k)];
      const Vector3 centre = 0.5 * (b.lo + b.hi), half = 0.5 * (b.hi - b.lo);
      if (n.dot(centre) - n.cwiseAbs().dot(half) - offset < 0.5 * margin) candidate(p, k);
    }
  }
  // A fixed order: by pair. Counting sort on the first geom (the sweep leaves them in any order), then
  // each first geom's few partners by insertion: linear in the pairs, where a comparison sort of a
  // crowded scene's thousands of pairs was a fifth of its detection.
  std::fill(first_count_.begin(), first_count_.end(), 0);
  for (int k = 0; k < npairs_; ++k) ++first_count_[static_cast<size_t>(pairs_[static_cast<size_t>(k)].first) + 1];
  for (size_t g = 1; g < first_count_.size(); ++g) first_count_[g] += first_count_[g - 1];
  for (int k = 0; k < npairs_; ++k) {
    const auto& p = pairs_[static_cast<size_t>(k)];
    sorted_[static_cast<size_t>(first_count_[static_cast<size_t>(p.first)]++)] = p;
  }
  std::swap(pairs_, sorted_);
  for (int k = 1; k < npairs_; ++k)  // equal first geoms are adjacent now: order their seconds
    for (int j = k; j > 0 && pairs_[static_cast<size_t>(j - 1)] > pairs_[static_cast<size_t>(j)]; --j)
      std::swap(pairs_[static_cast<size_t>(j - 1)], pairs_[static_cast<size_t>(j)]);
  out.n = 0;
  ContactPoint pts[kMaxPairPoints];
  for (int k = 0; k < npairs_; ++k) {
    const auto [i, j] = pairs_[static_cast<size_t>(k)];
    const Geom &a = geoms[static_cast<size_t>(i)], &b = geoms[static_cast<size_t>(j)];
    const int n = shapeContacts(*a.shape, pose_[static_cast<size_t>(i)], *b.shape, pose_[static_cast<size_t>(j)], margin, pts);
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
