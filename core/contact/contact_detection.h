// Finds the step's contacts: every pair of geoms that may touch
// (ContactModel::canTouch) and comes closer than the margin, each pair's
// points from shapeContacts (core/geometry/shape_contact.h). The broad phase
// (broad_phase.h) finds the candidate pairs from the geoms' bounding boxes;
// planes (the ground) are tested against every moving geom's box. The contacts come out
// ordered by geom pair and point, whatever order the sweep met them in, so a
// re-simulation meets the same contacts in the same order. Allocation-free
// after construction.
#pragma once

#include <vector>

#include "core/contact/broad_phase.h"
#include "core/contact/contact_model.h"
#include "core/contact/contact_set.h"
#include "core/model/data.h"

namespace igms {

class ContactDetection {
 public:
  explicit ContactDetection(const ContactModel& model);

  // The contacts at the poses in data.oMi (bodyKinematics at the step's start), into out
  // (cleared first; what does not fit is counted in out.dropped).
  void detect(const Data& data, ContactSet& out);

  int64_t candidatePairsDropped() const { return pairs_dropped_; }

 private:
  const ContactModel& cm_;
  std::vector<SE3> pose_;           // per geom, world
  std::vector<Aabb> box_;           // per geom, world, grown by the margin
  std::vector<Vector3> centre_;     // per geom, world: its bounding box's centre
  std::vector<double> reach_;       // per geom: a sphere about that centre that holds the shape
  std::vector<int> solids_;         // moving and fixed non-plane geoms
  BroadPhase broad_phase_;
  std::vector<int> planes_, moving_;
  std::vector<std::pair<int, int>> pairs_;  // candidates, capacity fixed
  std::vector<std::pair<int, int>> sorted_;  // the counting sort's output (swapped with pairs_)
  std::vector<int> first_count_;             // the counting sort's buckets, per geom
  int npairs_ = 0;
  int64_t pairs_dropped_ = 0;
};

}  // namespace igms
