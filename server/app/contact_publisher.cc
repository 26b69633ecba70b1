#include "server/app/contact_publisher.h"

#include <algorithm>
#include <cmath>

#include "channels.h"

namespace igms {

int contactPeriodSteps(double rate_hz, double contact_rate_hz) {
  if (!(contact_rate_hz > 0.0)) return 0;
  return std::max(1, static_cast<int>(std::lround(rate_hz / contact_rate_hz)));
}

ContactPublisher::ContactPublisher(bus::SignedPublisher& bus, int rows) : bus_(bus) {
  const auto n = static_cast<size_t>(std::min(rows, kMaxPublishedContacts));
  // The generated encoder reads ncontacts, not the vectors' sizes: full-size rows, no allocation per message.
  msg_.link_a.assign(n, -1);
  msg_.link_b.assign(n, -1);
  msg_.point.assign(n, std::vector<double>(3, 0.0));
  msg_.normal.assign(n, std::vector<double>(3, 0.0));
  msg_.force.assign(n, std::vector<double>(3, 0.0));
  msg_.distance.assign(n, 0.0);
  msg_.ncontacts = static_cast<int32_t>(n);
  buffer_.resize(static_cast<size_t>(msg_.getEncodedSize()) + 64 + bus::kTrailerBytes);  // signed in place
}

void ContactPublisher::publish(const Snapshot& s) {
  if (!s.contacts_due || msg_.link_a.empty()) return;
  msg_.utime = s.utime;
  msg_.seq = s.seq;
  msg_.sim_time = s.sim_time;
  msg_.total = s.contacts_total;
  msg_.dropped = s.contacts_dropped;
  msg_.ncontacts = std::min(s.ncontacts, static_cast<int>(msg_.link_a.size()));
  for (size_t k = 0; k < static_cast<size_t>(msg_.ncontacts); ++k) {
    const PublishedContact& c = s.contacts[k];
    msg_.link_a[k] = c.link_a;
    msg_.link_b[k] = c.link_b;
    for (int i = 0; i < 3; ++i) {
      msg_.point[k][static_cast<size_t>(i)] = c.point[i];
      msg_.normal[k][static_cast<size_t>(i)] = c.normal[i];
      msg_.force[k][static_cast<size_t>(i)] = c.force[i];
    }
    msg_.distance[k] = c.distance;
  }
  const int n = msg_.encode(buffer_.data(), 0, static_cast<int>(buffer_.size() - bus::kTrailerBytes));
  if (n <= 0) return;
  bus_.publishInPlace(channel_, buffer_.data(), static_cast<size_t>(n));
  ++sent_;
}

}  // namespace igms
