// TripleBuffer<T>: one writer publishes whole values (with heap members,
// preallocated) to one reader; neither ever waits for the other, and the
// reader always gets the newest complete value. Copies are by assignment, so
// equal-size vectors are reused without allocating.
#pragma once

#include <atomic>
#include <cstdint>

namespace igms {

template <typename T>
class TripleBuffer {
 public:
  explicit TripleBuffer(const T& initial) : slots_{initial, initial, initial} {}

  // Writer: fill back(), then publish().
  T& back() { return slots_[back_]; }
  void publish() {
    const uint8_t prev = middle_.exchange(static_cast<uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = prev & kIndex;
  }
  // Reader: true and *out updated when a newer value was published.
  bool take(T** out) {
    if (!(middle_.load(std::memory_order_acquire) & kFresh)) return false;
    const uint8_t prev = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = prev & kIndex;
    *out = &slots_[front_];
    return true;
  }

 private:
  static constexpr uint8_t kFresh = 4, kIndex = 3;
  T slots_[3];
  uint8_t back_ = 0, front_ = 1;
  std::atomic<uint8_t> middle_{2};
};

}  // namespace igms
