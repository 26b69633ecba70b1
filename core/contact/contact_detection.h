// Finds the step's contacts: every pair of geoms that may touch
// (ContactModel::canTouch) and comes closer than the margin, each pair's
// points from shapeContacts (core/geometry/shape_contact.h). A pair is a candidate
// when the geoms' bounding boxes overlap and the spheres about them come within
// the margin; planes (the ground) are tested against every moving geom's box.
// The candidates come from a list of the pairs near each other (a Verlet list, as
// molecular dynamics keeps one): the broad phase (broad_phase.h) finds the pairs
// within the margin and a skin, and the list serves until the geoms have moved
// more than the skin between them, so a resting pile runs no broad phase at all.
// The contacts come out ordered by geom pair and point, whatever order the broad
// phase met them in, so a re-simulation meets the same contacts in the same
// order. Allocation-free after construction.
#pragma once

#include <vector>

#include "core/contact/broad_phase.h"
#include "core/contact/contact_model.h"
#include "core/contact/contact_set.h"
#include "core/geometry/geometry_model.h"

namespace igms {

class ContactDetection {
 public:
  explicit ContactDetection(const ContactModel& model);

  // The contacts with the geometry placed at the step's start, into out (cleared first; what does not
  // fit is counted in out.dropped). Pairs name geoms by their geometry object's index.
  void detect(const GeometryData& placed, ContactSet& out);

  int64_t candidatePairsDropped() const { return pairs_dropped_; }
  // How many times the list of near pairs was rebuilt (the broad phase run).
  int64_t nearRebuilds() const { return rebuilds_; }
  double skin() const { return skin_; }

 private:
  // The stages of detect(), in order.
  // The geoms' boxes and bounding-sphere centres, at their placed poses.
  void place(const GeometryData& placed);
  // The candidate pairs among the solids, by pair: from the near list (rebuilt first if it no longer
  // holds), or straight from the broad phase when the list cannot be held.
  void broadPhase();
  // The planes' candidates (every moving geom whose box reaches below one), merged in by pair.
  void planeCandidates();
  // Each candidate's contact points (shapeContacts), with their pair's material, into out.
  void narrowPhase(ContactSet& out) const;
  // The pairs whose `boxes` overlap and whose bounding spheres come within `extra`, that may touch,
  // into out[0, n) (its capacity fixed) ordered by pair. \return how many did not fit.
  int findPairs(const std::vector<Aabb>& boxes, double extra, std::vector<std::pair<int, int>>& out, int& n);
  // Whether the near list still holds every candidate: no two geoms moved more than the skin between
  // them since it was built (and none left the finite).
  bool nearListHolds() const;

  const ContactModel& cm_;
  const SE3* pose_ = nullptr;       // per geom, world: the step's GeometryData
  std::vector<Aabb> box_;           // per geom, world, grown by the margin
  std::vector<Vector3> centre_;     // per geom, world: its bounding box's centre
  std::vector<double> reach_;       // per geom: a sphere about that centre that holds the shape
  std::vector<int> solids_;         // moving and fixed non-plane geoms
  BroadPhase broad_phase_;
  std::vector<int> planes_, moving_;
  std::vector<std::pair<int, int>> pairs_;  // candidates, capacity fixed
  std::vector<std::pair<int, int>> sorted_;  // the counting sort's output (swapped with pairs_)
  std::vector<int> first_count_;             // the counting sort's buckets, per geom
  std::vector<std::pair<int, int>> planar_;  // the step's plane candidates
  std::vector<std::pair<int, int>> near_;    // pairs within margin + skin when built, by pair
  std::vector<Aabb> wide_;                   // boxes grown by half the skin (the list's broad phase)
  std::vector<Vector3> built_centre_;        // per geom: its centre when the list was built
  double skin_ = 0.0;                        // m
  bool near_valid_ = false;
  int nnear_ = 0;
  int npairs_ = 0;
  int64_t pairs_dropped_ = 0;
  int64_t rebuilds_ = 0;
};

}  // namespace igms
