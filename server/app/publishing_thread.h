// The publishing side of the server: drains the snapshot ring into
// StatePublisher and sends the session info and the status when due.
// Realtime: a thread of its own, woken by each write into the ring and at
// least every 20 ms for the status. Lockstep: the loop pumps it itself (one
// thread hand-off fewer on the round trip).
#pragma once

#include <atomic>
#include <thread>

#include "server/app/contact_publisher.h"
#include "server/app/state_publisher.h"
#include "server/app/status_reporter.h"
#include "server/loop/snapshot.h"

namespace igms {

class PublishingThread {
 public:
  PublishingThread(SnapshotRing& ring, StatePublisher& states, ContactPublisher& contacts, StatusReporter& status)
      : ring_(ring), states_(states), contacts_(contacts), status_(status) {}
  ~PublishingThread() { finish(); }
  void start(bool threaded);
  // Publishes what the ring holds, and the session info and status when due.
  void pump();
  // Drains the ring, stops the thread, sends the final status (once).
  void finish();

 private:
  SnapshotRing& ring_;
  StatePublisher& states_;
  ContactPublisher& contacts_;
  StatusReporter& status_;
  std::atomic<bool> done_{false};
  bool finished_ = false;
  std::thread thread_;
};

}  // namespace igms
