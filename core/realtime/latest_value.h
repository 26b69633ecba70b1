// LatestValue<T>: one writer hands the newest value to one reader without
// locks (a seqlock). The reader never blocks the writer and always gets a
// consistent copy of the newest value. T must own no heap memory (fixed-size
// Eigen members are fine: they copy as plain arrays).
#pragma once

#include <atomic>
#include <cstdint>
#include <type_traits>

namespace igms {

template <typename T>
class LatestValue {
  static_assert(std::is_trivially_destructible_v<T>, "LatestValue needs a T without heap members");

 public:
  void write(const T& value) {
    const uint64_t s = seq_.load(std::memory_order_relaxed);
    seq_.store(s + 1, std::memory_order_relaxed);  // odd: writing
    std::atomic_thread_fence(std::memory_order_release);
    value_ = value;
    seq_.store(s + 2, std::memory_order_release);  // even: done
  }
  // Copies the newest value into *out. Returns its version (0: never written).
  uint64_t read(T* out) const {
    for (;;) {
      const uint64_t s1 = seq_.load(std::memory_order_acquire);
      if (s1 & 1u) continue;
      *out = value_;
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) == s1) return s1 / 2;
    }
  }
  uint64_t version() const { return seq_.load(std::memory_order_acquire) / 2; }

 private:
  std::atomic<uint64_t> seq_{0};
  T value_{};
};

}  // namespace igms
