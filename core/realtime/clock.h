// The two clocks of igms processes: a monotonic one for durations and
// deadlines, and wall time in microseconds for message utime (LCM's habit).
#pragma once

#include <time.h>

#include <chrono>
#include <cstdint>

namespace igms {

// Seconds on CLOCK_MONOTONIC (what clock_nanosleep's absolute deadlines use).
inline double monotonicSeconds() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Microseconds since the Unix epoch.
inline int64_t wallMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace igms
