// Finds the step's contacts: every pair of geoms that may touch
// (ContactModel::canTouch) and comes closer than the margin, each pair's
// points from shapeContacts (core/geometry/shape_contact.h). A sweep over the
// geoms' bounding boxes along one axis finds the candidate pairs; planes (the
// ground) are tested against every moving geom's box. The contacts come out
// ordered by geom pair and point, whatever order the sweep met them in, so a
// re-simulation meets the same contacts in the same order. Allocation-free
// after construction.
#pragma once

#include <vector>

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
  struct Box {
    Vector3 lo, hi;
  };
  const ContactModel& cm_;
  std::vector<SE3> pose_;           // per geom, world
  std::vector<Box> box_;            // per geom, world, grown by the margin
  std::vector<int> order_;          // moving and fixed non-plane geoms, by box lo along the sweep axis
  std::vector<int> planes_, moving_;
  std::vector<std::pair<int, int>> pairs_;  // candidates, capacity fixed
  std::vector<std::pair<int, int>> sorted_;  // the counting sort's output (swapped with pairs_)
  std::vector<int> first_count_;             // the counting sort's buckets, per geom
  int npairs_ = 0;
  int64_t pairs_dropped_ = 0;
};

}  // namespace igms
