// The server's status (IGMS_SERVER_STATUS, about 10 Hz, and one line on
// stderr unless quiet), its bus status (IGMS_BUS_STATUS, 1 Hz: the message checks' counts) and the session info a replay needs
// (IGMS_SESSION_INFO, with every robot's files on IGMS_SESSION_FILES: at the start, after a reset, and every second).
// Runs on the publishing thread; any thread may ask for the session info.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "bus/signed_publisher.h"
#include "core/simulation/simulation.h"
#include "igms/server_status_t.hpp"
#include "igms/session_files_t.hpp"
#include "igms/session_info_t.hpp"
#include "server/app/state_publisher.h"
#include "server/loop/loop_status.h"
#include "server/transport/bus_receiver.h"

namespace igms {

class StatusReporter {
 public:
  // hold_s: how long a client's input keeps its coupling acting (the status calls a client active within it).
  StatusReporter(bus::SignedPublisher& bus, const Simulation& sim, const std::string& clock, BusReceiver& receiver,
                 LoopStatus& loop, bool quiet, double hold_s);

  // A new session token: the next pump sends the session info with it.
  void requestSessionInfo(int64_t token);
  // The session info, when asked for (before any state: a log starts with it).
  void pumpSessionInfo();
  // The status, every 100 ms.
  void pumpStatus(PublishStats& published);
  // The status now, whether due or not (the final one).
  void publishStatus(PublishStats& published);

 private:
  void print(const server_status_t& s, const PublishStats& p) const;

  bus::SignedPublisher& bus_;
  BusReceiver& receiver_;
  LoopStatus& loop_;
  bool quiet_;
  double hold_s_;
  session_info_t info_;
  session_files_t files_;  // sent with each session info
  std::atomic<bool> info_due_{false};
  std::atomic<int64_t> token_{0};
  std::string scene_;
  std::vector<std::string> link_names_, components_;
  int64_t seq_ = 0;
  double window_start_, next_status_;
};

}  // namespace igms
