// The 1 kHz servo loop on absolute deadlines. Each cycle:
//   1. read the device and map it into the scene;
//   2. send the input (push contact as seen, or pull attachment) with seq k;
//   3. take every state newer than the one it has; while echoes come back
//      within the deadline (a near server), wait that long for this cycle's;
//   4. estimate the robot as it will be when this cycle's input reaches the
//      server: the newest state carried over the inputs it has not seen yet
//      (the ones after the input it echoes; without an echo, over its age:
//      the time since it arrived plus half the smallest round trip of the
//      last second). With the predict policy that is the local model while
//      any of those inputs interacts, else q + v h + qdd h^2/2; hold,
//      extrapolate and interpolate work on link poses as before. Then the
//      contact force (eq. 3) or the spring force (eq. 4) against it, rendered
//      through the guards (start-up guard, server-lost ramp, resync blend,
//      passivity controller, the device's limit, the per-cycle bound).
//      "Server lost" is no new state for lost_ms, whatever the echoes.
// Nothing in a cycle allocates, locks or does I/O beyond the non-blocking
// publish of its input.
#pragma once

#include <atomic>
#include <memory>
#include <vector>

#include "haptic_client/device/haptic_device.h"
#include "haptic_client/device/workspace_map.h"
#include "haptic_client/servo/client_bus.h"
#include "haptic_client/servo/client_interaction.h"
#include "haptic_client/servo/local_model.h"
#include "haptic_client/servo/servo_record.h"
#include "haptic_client/servo/servo_stats.h"

namespace igms {

struct ServoConfig {
  double rate_hz = 1000.0;
  double deadline_us = 900.0;  // wait for this cycle's state at most this long after the cycle starts
  double lost_ms = 50.0;       // no new state for this long: the server is lost, forces ramp down
  double duration = 0.0;       // s; 0: until the device's script ends (or forever)
  int client_id = 1;
  // The local model's compute per cycle (sets how many steps it may take): 600 µs, where 150 left the
  // estimate of a slow slide over a 20 ms bus behind the tip and the felt force swinging by 1.2 N
  // (docs/client.md), and the loop held 1000 Hz.
  double local_budget_us = 600.0;
  bool passivity = true;           // the time-domain passivity controller at the device port
  double passivity_tolerance = 0.025;  // J the energy balance may dip before it acts
  // A device read that blocks longer than this (a plugin stuck on its driver): the device is held as
  // lost for as long as it blocked (at least lost_ms), so the force ramps out as for a lost device.
  double blocked_read_ms = 5.0;
};

class ServoLoop {
 public:
  // links: the estimate's link poses, which the device may read (scripted link targets).
  // record: where each cycle's tip and forces go (null, or one that is off: nowhere).
  ServoLoop(const ResolvedScene& scene, HapticDevice& device, ClientBus& bus, StateEstimate& estimate,
            std::vector<SE3>& links, ServoStats& stats, const ServoConfig& config, ServoRecord* record = nullptr);
  // Runs until stopped, the duration, or the end of the device's script. Returns the wall time, s.
  double run(const std::atomic<bool>& stop);

 private:
  void cycle(int64_t k, double nominal_start);
  bool awaitState(int64_t k, double nominal_start);
  void take(const ReceivedState& r);
  void render(int64_t k, const Vector3& tip, const Vector3& tip_velocity, bool on_time, bool device_lost);
  double oneWayDelay() const;
  // The robot for this cycle's force (into links_); returns the horizon, s.
  double estimateRobot(int64_t k, double age, bool on_time);

  const ServoConfig config_;
  const double period_, sim_dt_;
  const RenderLimits render_limits_;
  const DeviceLimits device_limits_;
  double blocked_until_ = -1.0;   // monotonic s: a blocked read holds the device as lost until then
  double phase_lag_ = 0.0;        // this cycle: how late an echo came that another hand's input held back, s
  int64_t last_phase_shift_ = -1000;
  const WorkspaceMap map_;
  HapticDevice& device_;
  ClientBus& bus_;
  StateEstimate& estimate_;
  std::vector<SE3>& links_;
  std::vector<Motion> link_velocities_;  // the estimate's, for the coupling's damper
  ServoStats& stats_;
  ServoRecord* record_;
  ClientInteraction interaction_;
  SentInputs sent_inputs_;
  std::unique_ptr<LocalModel> local_;  // with the predict policy
  haptic_input_t msg_{};
  int64_t consecutive_misses_ = 0;
  double estimate_time_ = 0.0;  // simulated time the estimate is for (the newest state's plus its age)
  bool resync_ = false;         // a state arrived after a gap in arrivals
  bool realtime_ = false;       // the loop's thread runs under SCHED_FIFO or SCHED_RR (asked before run())
  // The smallest round trip (from the echoes and sent_inputs_' send times) in this and the last half second.
  double rtt_min_now_ = 1e9, rtt_min_before_ = 1e9, rtt_window_start_ = 0.0;
};

}  // namespace igms
