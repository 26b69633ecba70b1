// Real-time scheduling on request: SCHED_FIFO for the calling thread and
// locked memory (no page faults in the loop), or a clear reason why not
// (without CAP_SYS_NICE or an rtprio limit, Linux says EPERM). Called once,
// at start, by the thread that runs the loop; never from inside it.
#pragma once

#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

namespace igms {

// priority 1..99. Returns "" on success, else what failed (the caller warns and runs on).
inline std::string requestRealtime(int priority) {
  sched_param p{};
  p.sched_priority = priority;
  if (sched_setscheduler(0, SCHED_FIFO, &p) != 0)
    return std::string("SCHED_FIFO priority ") + std::to_string(priority) + ": " + std::strerror(errno) +
           " (needs CAP_SYS_NICE or an rtprio limit, e.g. run with sudo or set @realtime - rtprio 99)";
  if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0)
    return std::string("memory lock: ") + std::strerror(errno) + " (SCHED_FIFO is on; pages may still fault)";
  return "";
}

// The same, said on stderr in one line either way ("igms-server: loop on ...").
inline void requestRealtimeAndSay(const char* program, const char* loop, int priority) {
  const std::string why = requestRealtime(priority);
  if (why.empty())
    std::fprintf(stderr, "%s: %s on SCHED_FIFO priority %d, memory locked\n", program, loop, priority);
  else
    std::fprintf(stderr, "%s: warning: no real-time scheduling: %s; running on as a normal process\n", program,
                 why.c_str());
}

}  // namespace igms
