#include "tools/relay/delay_line.h"

#include <algorithm>
#include <limits>

namespace igms {

DelayLine::DelayLine(const PathFaults& faults, uint32_t seed) : faults_(faults), rng_(seed) {}

void DelayLine::admit(const std::string& channel, const uint8_t* data, size_t size, double now) {
  ++counts_.received;
  const int64_t order = next_order_++;
  if (faults_.loss > 0.0 && unit_(rng_) < faults_.loss) {
    ++counts_.dropped;
    return;
  }
  if (queue_.size() >= faults_.max_queue) {
    ++counts_.overflowed;
    return;
  }
  const double jitter = faults_.jitter_ms > 0.0 ? (2.0 * unit_(rng_) - 1.0) * faults_.jitter_ms : 0.0;
  double release = now + std::max(0.0, faults_.delay_ms + jitter) * 1e-3;
  if (faults_.in_order) release = std::max(release, last_release_);
  last_release_ = std::max(last_release_, release);
  queue_.push(HeldMessage{release, order, channel, std::vector<uint8_t>(data, data + size)});
  counts_.max_queued = std::max(counts_.max_queued, queue_.size());
}

bool DelayLine::popDue(double now, HeldMessage* out) {
  if (queue_.empty() || queue_.top().release > now) return false;
  // priority_queue::top is const: the copy is the price of std's heap (a relay, not a servo loop).
  *out = queue_.top();
  queue_.pop();
  if (out->order < last_forwarded_order_) ++counts_.reordered;
  last_forwarded_order_ = std::max(last_forwarded_order_, out->order);
  ++counts_.forwarded;
  return true;
}

double DelayLine::nextRelease() const {
  return queue_.empty() ? std::numeric_limits<double>::infinity() : queue_.top().release;
}

}  // namespace igms
