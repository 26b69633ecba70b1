// How an igms process is stopped: SIGINT and SIGTERM set one flag its loops
// poll (the handler only stores to a lock-free atomic). Installing it also
// sets the timer slack to 1 us, so sleeps wake within 1 us of their time
// instead of the default 50 us.
#pragma once

#include <sys/prctl.h>

#include <atomic>
#include <csignal>

namespace igms {

inline std::atomic<bool>& stopRequested() {
  static std::atomic<bool> flag{false};
  return flag;
}

inline std::atomic<bool>& stopOnSignals() {
  prctl(PR_SET_TIMERSLACK, 1000UL, 0, 0, 0);
  std::signal(SIGINT, [](int) { stopRequested() = true; });
  std::signal(SIGTERM, [](int) { stopRequested() = true; });
  return stopRequested();
}

}  // namespace igms
