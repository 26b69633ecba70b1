// The haptic client (igms-haptic): a 1 kHz servo loop on absolute deadlines.
// Each cycle:
//   read the device and map it into the scene;
//   send the input (push contact as seen, or pull attachment) with seq k;
//   wait for the server's state for this cycle only until the deadline;
//   on time: use it; late: a fallback estimate (hold / extrapolate / interpolate);
//   compute the contact force (eq. 3) or the spring force (eq. 4) against the
//   estimate and render its reaction: start-up guard, server-lost ramp, limits.
// The bus thread decodes states into a triple buffer (no locks between the
// two) and publishes the client status at 10 Hz. The servo loop never
// allocates, locks or does I/O beyond the non-blocking publish of its input.
#pragma once

#include <atomic>
#include <string>

namespace igms {

struct ClientOptions {
  std::string scene_path;
  std::string device;          // "scripted:FILE"
  std::string lcm_url;
  double rate_hz = 1000.0;
  double deadline_us = 900.0;  // wait for this cycle's state at most this long after the cycle starts
  std::string fallback = "hold";
  double lost_ms = 50.0;       // no state for this long: the server is lost, forces ramp down
  int client_id = 1;
  double duration = 0.0;       // s; 0: until the device's script ends (or forever)
  double connect_timeout = 10.0;  // s to wait for the server's first status
  bool quiet = false;
};

// Returns the exit code: 0 done, 2 setup error, 3 no server.
int runClient(const ClientOptions& options, const std::atomic<bool>& stop);

}  // namespace igms
