// igms-server: runs a scene at its rate, takes haptic inputs and commands from
// LCM, publishes the robot state every step and a status at about 10 Hz.
//
// Composed of named parts (docs/architecture.md has the picture):
//   BusReceiver (transport/)   inputs validated and handed over lock-free; commands queued
//   Stepper (loop/)            the newest input, one Simulation step, its snapshot into the ring
//   applyCommand (loop/)       commands between steps, validated, rejections counted
//   StatePublisher (app/)      snapshots -> robot_state_t, the FCL obstacle check, fault injection
//   ContactPublisher (app/)    snapshots' contacts -> contacts_t, at --contact-rate
//   StatusReporter (app/)      server_status_t and session_info_t
//   PublishingThread (app/)    drains the ring into the three above
// Threads: the loop (this one: steps on absolute deadlines, or one step per
// input in lockstep, where it also receives and publishes), the bus thread
// (realtime only) and the publishing thread (realtime only).
#pragma once

#include <atomic>
#include <string>

#include "server/loop/command_policy.h"

namespace igms {

struct ServerOptions {
  std::string scene_path;
  std::string lcm_url;
  enum class Clock { Realtime, Lockstep } clock = Clock::Realtime;
  double duration = 0.0;        // s of simulated time, 0: until stopped
  std::string save_edited;      // write the edited trajectory here on exit
  int64_t session_token = 0;    // 0: random
  bool start_paused = false;
  double input_hold = 0.05;     // s: an input keeps acting this long without a newer one
  bool quiet = false;
  int rt_priority = 0;          // > 0: the loop asks for SCHED_FIFO at this priority and locks memory
  CommandPolicy commands;       // scene folders, output folder
  std::string key_file;         // the bus key (bus/bus_key.h): sign and check every message; "": unauthenticated
  bool accept_replay = false;   // take replayed traffic (igms-replay play) too
  // Fault injection on the published states (tests of the client's fallback):
  double fault_drop = 0.0;       // fraction of states not published
  double fault_burst_ms = 0.0;   // every second, no states for this long
  double fault_delay_us = 0.0;   // every state published this much later
  double contact_rate = 100.0;   // Hz at most on IGMS_CONTACTS (0: none; scenes with contact only)
};

// Runs until stopped (stop flag, SHUTDOWN command, duration, or divergence).
// Returns the process exit code: 0 clean, 1 diverged, 2 bad scene or bus.
int runServer(const ServerOptions& options, const std::atomic<bool>& stop);

}  // namespace igms
