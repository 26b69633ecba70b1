// Absolute deadlines on CLOCK_MONOTONIC for periodic loops (the server's
// realtime clock, the client's servo loop), and a CLOCK_REALTIME time a
// timed semaphore wait can take. The one place igms does timespec arithmetic.
#pragma once

#include <time.h>

#include <cstdint>

namespace igms {

inline timespec addNanoseconds(timespec t, int64_t ns) {
  t.tv_sec += static_cast<time_t>(ns / 1000000000LL);
  t.tv_nsec += static_cast<long>(ns % 1000000000LL);
  if (t.tv_nsec >= 1000000000L) {
    t.tv_nsec -= 1000000000L;
    ++t.tv_sec;
  }
  return t;
}

inline bool isBefore(const timespec& a, const timespec& b) {
  return a.tv_sec < b.tv_sec || (a.tv_sec == b.tv_sec && a.tv_nsec < b.tv_nsec);
}

// `seconds` from now on CLOCK_REALTIME (what sem_timedwait wants).
inline timespec realtimeIn(double seconds) {
  timespec now;
  clock_gettime(CLOCK_REALTIME, &now);
  return addNanoseconds(now, static_cast<int64_t>(seconds * 1e9));
}

// A train of deadlines one period apart, starting now. A late cycle still
// aims the next one at its own deadline (no drift).
class PeriodicDeadline {
 public:
  explicit PeriodicDeadline(double period_s) : period_ns_(static_cast<int64_t>(period_s * 1e9)) {
    clock_gettime(CLOCK_MONOTONIC, &next_);
  }
  // Sleeps until the current deadline (at once when it has passed).
  void sleep() const { clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next_, nullptr); }
  void advance() { next_ = addNanoseconds(next_, period_ns_); }
  // Moves the train later by `seconds` (a phase shift; the period stays).
  void delay(double seconds) { next_ = addNanoseconds(next_, static_cast<int64_t>(seconds * 1e9)); }
  bool passed() const {
    timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    return isBefore(next_, now);
  }
  // The current deadline, s on CLOCK_MONOTONIC (monotonicSeconds()'s clock).
  double at() const { return static_cast<double>(next_.tv_sec) + 1e-9 * static_cast<double>(next_.tv_nsec); }
  // The catch-up rule's second half: more than max_late periods behind, the
  // train restarts from now and the missed periods are skipped (returned).
  int64_t skipIfBehind(int64_t max_late) {
    timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    const int64_t late_ns = (now.tv_sec - next_.tv_sec) * 1000000000LL + (now.tv_nsec - next_.tv_nsec);
    const int64_t periods = late_ns / period_ns_;
    if (periods <= max_late) return 0;
    next_ = addNanoseconds(next_, periods * period_ns_);
    return periods;
  }

 private:
  int64_t period_ns_;
  timespec next_;
};

}  // namespace igms
