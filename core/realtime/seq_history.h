// SeqHistory<T, N>: one writer keeps the last N values it wrote, each under its
// key (a client's input seq), and one reader finds a value by its key without
// locks. A key's slot is key mod N, each slot a LatestValue of the key and its
// value, so a value stays findable until the key N later overwrites it. T must
// own no heap memory.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "core/realtime/latest_value.h"

namespace igms {

template <typename T, int N>
class SeqHistory {
  static_assert(N > 0);

 public:
  void write(int64_t key, const T& value) { slots_[index(key)].write(Keyed{key, value}); }
  // Copies the value written under `key` into *out. \return false when it was never written or the
  // key N later has taken its slot.
  bool read(int64_t key, T* out) const {
    Keyed k;
    slots_[index(key)].read(&k);
    if (k.key != key) return false;
    *out = k.value;
    return true;
  }

 private:
  struct Keyed {
    int64_t key = -1;  // never written
    T value{};
  };
  static std::size_t index(int64_t key) { return static_cast<std::size_t>(((key % N) + N) % N); }
  std::array<LatestValue<Keyed>, N> slots_;
};

}  // namespace igms
