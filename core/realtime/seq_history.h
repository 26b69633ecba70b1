// SeqHistory<T, N>: one writer keeps the last N values it wrote, each under its
// key (a client's input seq), and one reader finds a value by its key without
// locks (a seqlock per slot, as in LatestValue). A key's slot is key mod N, so
// a value stays findable until the key N later overwrites it. T must own no
// heap memory.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <type_traits>

namespace igms {

template <typename T, int N>
class SeqHistory {
  static_assert(std::is_trivially_destructible_v<T>, "SeqHistory needs a T without heap members");
  static_assert(N > 0);

 public:
  void write(int64_t key, const T& value) {
    Slot& s = slots_[index(key)];
    const uint64_t l = s.lock.load(std::memory_order_relaxed);
    s.lock.store(l + 1, std::memory_order_relaxed);  // odd: writing
    std::atomic_thread_fence(std::memory_order_release);
    s.key = key;
    s.value = value;
    s.lock.store(l + 2, std::memory_order_release);  // even: done
  }
  // Copies the value written under `key` into *out. \return false when it was never written or the
  // key N later has taken its slot.
  bool read(int64_t key, T* out) const {
    const Slot& s = slots_[index(key)];
    for (;;) {
      const uint64_t l1 = s.lock.load(std::memory_order_acquire);
      if (l1 & 1u) continue;
      const bool found = s.key == key;
      if (found) *out = s.value;
      std::atomic_thread_fence(std::memory_order_acquire);
      if (s.lock.load(std::memory_order_relaxed) == l1) return found;
    }
  }

 private:
  struct Slot {
    std::atomic<uint64_t> lock{0};
    int64_t key = -1;
    T value{};
  };
  static size_t index(int64_t key) { return static_cast<size_t>(((key % N) + N) % N); }
  std::array<Slot, N> slots_;
};

}  // namespace igms
