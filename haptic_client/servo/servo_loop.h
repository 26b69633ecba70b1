// The 1 kHz servo loop on absolute deadlines. Each cycle:
//   1. read the device and map it into the scene;
//   2. send the input (push contact as seen, or pull attachment) with seq k;
//   3. wait for the server's state for this cycle only until the deadline;
//   4. on time: use it; late: a fallback estimate (hold / extrapolate / interpolate);
//      the contact force (eq. 3) or the spring force (eq. 4) against the
//      estimate, and its reaction rendered through the guards (start-up
//      guard, server-lost ramp, resync blend, the device's limit).
// Nothing in a cycle allocates, locks or does I/O beyond the non-blocking
// publish of its input.
#pragma once

#include <atomic>
#include <vector>

#include "haptic_client/device/haptic_device.h"
#include "haptic_client/device/workspace_map.h"
#include "haptic_client/servo/client_bus.h"
#include "haptic_client/servo/client_interaction.h"
#include "haptic_client/servo/servo_stats.h"

namespace igms {

struct ServoConfig {
  double rate_hz = 1000.0;
  double deadline_us = 900.0;  // wait for this cycle's state at most this long after the cycle starts
  double lost_ms = 50.0;       // no state for this long: the server is lost, forces ramp down
  double duration = 0.0;       // s; 0: until the device's script ends (or forever)
  int client_id = 1;
};

class ServoLoop {
 public:
  // links: the estimate's link poses, which the device may read (scripted link targets).
  ServoLoop(const ResolvedScene& scene, HapticDevice& device, ClientBus& bus, StateEstimate& estimate,
            std::vector<SE3>& links, ServoStats& stats, const ServoConfig& config);
  // Runs until stopped, the duration, or the end of the device's script. Returns the wall time, s.
  double run(const std::atomic<bool>& stop);

 private:
  void cycle(int64_t k, double cycle_start);
  bool awaitState(int64_t k, double cycle_start, double sent);
  void render(const Vector3& tip, const Vector3& tip_velocity, bool on_time);

  const ServoConfig config_;
  const double period_, sim_dt_;
  const WorkspaceMap map_;
  HapticDevice& device_;
  const DeviceLimits limits_;
  ClientBus& bus_;
  StateEstimate& estimate_;
  std::vector<SE3>& links_;
  ServoStats& stats_;
  ClientInteraction interaction_;
  haptic_input_t msg_{};
  int64_t consecutive_misses_ = 0;
  double expected_time_ = 0.0;  // simulated time of this cycle's state
};

}  // namespace igms
