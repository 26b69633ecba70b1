// What one step hands to the publishing thread: a preallocated slot in a
// single-producer single-consumer ring. The step copies into it; nothing
// allocates. The consumer may sleep until a slot is written (a futex post
// per write, no lock).
#pragma once

#include <semaphore.h>

#include <algorithm>
#include <atomic>
#include <vector>

#include "core/realtime/deadline.h"

#include "core/simulation/simulation.h"

namespace igms {

// One contact as published: the link on each side (-1: the world), where, and the force.
struct PublishedContact {
  int32_t link_a = -1, link_b = -1;
  Vector3 point = Vector3::Zero(), normal = Vector3::UnitZ(), force = Vector3::Zero();  // force: on b, N
  double distance = 0.0;
};
// The contacts one state carries at most: what one datagram holds with room to
// spare (contacts_t is 88 bytes a contact); the rest is counted in `total`.
constexpr int kMaxPublishedContacts = 512;

struct Snapshot {
  int64_t seq = 0;
  double sim_time = 0.0;
  int64_t utime = 0;
  int32_t step_us = 0;
  StepOutcome outcome;
  std::vector<double> q, v, qdd, tau;
  std::vector<SE3> link_poses;
  // Filled on the steps the contact channel is due (contacts_due), else left stale.
  ContactSolveStats solve;  // the contact solver's, after this step (solved: the step had contacts)
  bool solved = false;
  int64_t candidates_dropped = 0;     // contact detection's pairs dropped (a crowd beyond its buffers), total
  int64_t proxy_substep_limited = 0;  // hands' proxy cycles cut short by the substep budget, total
  bool contacts_due = false;
  int ncontacts = 0, contacts_total = 0;
  int64_t contacts_dropped = 0;
  std::vector<PublishedContact> contacts;
  void size(const Model& m, int contact_rows) {
    q.assign(static_cast<size_t>(m.nq), 0.0);
    v.assign(static_cast<size_t>(m.nv), 0.0);
    qdd.assign(static_cast<size_t>(m.nv), 0.0);
    tau.assign(static_cast<size_t>(m.nv), 0.0);
    link_poses.assign(m.frames.size(), SE3::Identity());
    contacts.assign(static_cast<size_t>(std::min(contact_rows, kMaxPublishedContacts)), PublishedContact{});
  }
};

class SnapshotRing {
 public:
  // contact_rows: the contact buffer's capacity (0 for a scene without contact).
  SnapshotRing(const Model& m, size_t capacity, int contact_rows) : slots_(capacity) {
    for (auto& s : slots_) s.size(m, contact_rows);
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

// The contacts of the last step into the snapshot (no allocation: at most its rows).
inline void takeContacts(const Simulation& sim, Snapshot& s) {
  const ContactSet& set = sim.contacts();
  const ContactModel* cm = sim.contactModel();
  s.contacts_total = set.n;
  s.contacts_dropped = set.dropped;
  s.ncontacts = std::min(set.n, static_cast<int>(s.contacts.size()));
  const double inv_dt = 1.0 / sim.scene().dt;
  for (int k = 0; k < s.ncontacts; ++k) {
    const Contact& c = set[k];
    PublishedContact& p = s.contacts[static_cast<size_t>(k)];
    p.link_a = cm ? cm->geom(c.geom_a).frame : -1;
    p.link_b = cm ? cm->geom(c.geom_b).frame : -1;
    p.point = c.point;
    p.normal = c.normal;
    p.force = c.impulse * inv_dt;
    p.distance = c.distance;
  }
}

// Fills a snapshot from the simulation (no allocation: sizes match).
inline void takeSnapshot(Simulation& sim, int64_t utime, int32_t step_us, bool contacts_due, Snapshot& s) {
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
  s.solve = sim.contactStats();
  s.solved = sim.contacts().n > 0;
  s.candidates_dropped = sim.contactDetection() ? sim.contactDetection()->candidatePairsDropped() : 0;
  s.proxy_substep_limited = sim.proxySubstepLimited();
  s.contacts_due = contacts_due && !s.contacts.empty();
  if (s.contacts_due) takeContacts(sim, s);
}

}  // namespace igms
