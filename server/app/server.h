// igms-server: runs a scene at its rate, takes haptic inputs and commands from
// LCM, publishes the robot state every step and a status at about 10 Hz.
//
// Threads: the simulation thread (this one: steps on absolute deadlines, or
// one step per input in lockstep), the bus thread (receives, validates and
// hands the newest input over lock-free), and the publishing thread (encodes
// and publishes states from a ring of snapshots, checks collisions, status).
#pragma once

#include <atomic>
#include <string>

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
  // Fault injection on the published states (tests of the client's fallback):
  double fault_drop = 0.0;       // fraction of states not published
  double fault_burst_ms = 0.0;   // every second, no states for this long
  double fault_delay_us = 0.0;   // every state published this much later
};

// Runs until stopped (stop flag, SHUTDOWN command, duration, or divergence).
// Returns the process exit code: 0 clean, 1 diverged, 2 bad scene or bus.
int runServer(const ServerOptions& options, const std::atomic<bool>& stop);

}  // namespace igms
