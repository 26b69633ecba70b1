// What one step hands to the publishing thread: a preallocated slot in a
// single-producer single-consumer ring. The step copies into it; nothing
// allocates. The consumer may sleep until a slot is written (a futex post
// per write, no lock).
#pragma once

#include <semaphore.h>

#include <atomic>
#include <vector>

#include "core/realtime/deadline.h"

#include "core/simulation/simulation.h"

namespace igms {

struct Snapshot {
  int64_t seq = 0;
  double sim_time = 0.0;
  int64_t utime = 0;
  int32_t step_us = 0;
  StepOutcome outcome;
  std::vector<double> q, v, qdd, tau;
  std::vector<SE3> link_poses;
  void size(const Model& m) {
    q.assign(static_cast<size_t>(m.nq), 0.0);
    v.assign(static_cast<size_t>(m.nv), 0.0);
    qdd.assign(static_cast<size_t>(m.nv), 0.0);
    tau.assign(static_cast<size_t>(m.nv), 0.0);
    link_poses.assign(m.frames.size(), SE3::Identity());
  }
};

class SnapshotRing {
 public:
  SnapshotRing(const Model& m, size_t capacity) : slots_(capacity) {
    for (auto& s : slots_) s.size(m);
    sem_init(&written_, 0, 0);
  }
  ~SnapshotRing() { sem_destroy(&written_); }
  SnapshotRing(const SnapshotRing&) = delete;
  SnapshotRing& operator=(const SnapshotRing&) = delete;
  // Producer: the slot to fill, or null when the ring is full (the caller counts a drop).
  Snapshot* beginWrite() {
    const size_t h = head_.load(std::memory_order_relaxed);
    if (h - tail_.load(std::memory_order_acquire) >= slots_.size()) return nullptr;
    return &slots_[h % slots_.size()];
  }
  void endWrite() {
    head_.store(head_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
    sem_post(&written_);
  }
  // Consumer.
  const Snapshot* beginRead() {
    const size_t t = tail_.load(std::memory_order_relaxed);
    if (t == head_.load(std::memory_order_acquire)) return nullptr;
    return &slots_[t % slots_.size()];
  }
  void endRead() { tail_.store(tail_.load(std::memory_order_relaxed) + 1, std::memory_order_release); }
  // Sleeps until a write (or a wake()) or for at most `seconds`.
  void waitForWrite(double seconds) {
    const timespec until = realtimeIn(seconds);
    sem_timedwait(&written_, &until);
  }
  void wake() { sem_post(&written_); }

 private:
  std::vector<Snapshot> slots_;
  std::atomic<size_t> head_{0}, tail_{0};
  sem_t written_;
};

// Fills a snapshot from the simulation (no allocation: sizes match).
inline void takeSnapshot(Simulation& sim, int64_t utime, int32_t step_us, Snapshot& s) {
  s.seq = sim.steps();
  s.sim_time = sim.time();
  s.utime = utime;
  s.step_us = step_us;
  s.outcome = sim.outcome();
  for (int i = 0; i < sim.q().size(); ++i) s.q[static_cast<size_t>(i)] = sim.q()[i];
  for (int i = 0; i < sim.v().size(); ++i) {
    s.v[static_cast<size_t>(i)] = sim.v()[i];
    s.qdd[static_cast<size_t>(i)] = sim.qdd()[i];
    s.tau[static_cast<size_t>(i)] = sim.tau()[i];
  }
  const auto& poses = sim.linkPoses();
  for (size_t f = 0; f < poses.size(); ++f) s.link_poses[f] = poses[f];
}

}  // namespace igms
