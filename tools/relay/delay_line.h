// One direction of igms-relay: what a network path does to datagrams. Each
// message is dropped with probability `loss`, else released after
// `delay_ms` plus a uniform jitter in [-jitter_ms, +jitter_ms] (never
// negative). With jitter, later messages may be released before earlier ones
// (reordering, as on a real path) unless `in_order` holds them back.
// Everything it does is counted.
#pragma once

#include <cstdint>
#include <queue>
#include <random>
#include <string>
#include <vector>

namespace igms {

struct PathFaults {
  double delay_ms = 0.0;
  double jitter_ms = 0.0;
  double loss = 0.0;       // probability in [0, 1]
  bool in_order = false;   // jitter without reordering
  size_t max_queue = 200000;  // messages held at once; more are dropped (counted as overflow)
};

struct PathCounts {
  int64_t received = 0, forwarded = 0, dropped = 0, overflowed = 0, reordered = 0;
  size_t max_queued = 0;
};

struct HeldMessage {
  double release = 0.0;  // s, the caller's clock
  int64_t order = 0;     // arrival order
  std::string channel;
  std::vector<uint8_t> data;
};

class DelayLine {
 public:
  DelayLine(const PathFaults& faults, uint32_t seed);

  // A message arrived at time `now` (s).
  void admit(const std::string& channel, const uint8_t* data, size_t size, double now);
  // The next message due at `now`, if any (moved out).
  bool popDue(double now, HeldMessage* out);
  // When the next message is due (s), or +inf when none is held.
  double nextRelease() const;

  const PathFaults& faults() const { return faults_; }
  const PathCounts& counts() const { return counts_; }
  size_t queued() const { return queue_.size(); }

 private:
  struct Later {
    bool operator()(const HeldMessage& a, const HeldMessage& b) const {
      return a.release != b.release ? a.release > b.release : a.order > b.order;
    }
  };
  PathFaults faults_;
  std::mt19937_64 rng_;
  std::uniform_real_distribution<double> unit_{0.0, 1.0};
  std::priority_queue<HeldMessage, std::vector<HeldMessage>, Later> queue_;
  PathCounts counts_;
  int64_t next_order_ = 0, last_forwarded_order_ = -1;
  double last_release_ = 0.0;
};

}  // namespace igms
