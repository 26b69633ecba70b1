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
};

// Runs until stopped (stop flag, SHUTDOWN command, duration, or divergence).
// Returns the process exit code: 0 clean, 1 diverged, 2 bad scene or bus.
int runServer(const ServerOptions& options, const std::atomic<bool>& stop);

}  // namespace igms
