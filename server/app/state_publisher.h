// Snapshots of the step -> robot_state_t on IGMS_ROBOT_STATE, with the FCL
// obstacle check of each published pose. Encodes into a preallocated buffer
// and publishes raw bytes (LCM's typed publish allocates per call). Optional
// fault injection (drop, bursts, delay) for tests of the client's fallbacks;
// with faults on, every state also goes to IGMS_ROBOT_STATE_TRUTH so a log
// re-simulates. Runs on the publishing thread only.
#pragma once

#include <random>
#include <vector>

#include <string>

#include "bus/signed_publisher.h"
#include "channels.h"
#include "igms/robot_state_t.hpp"
#include "server/app/joint_limit_report.h"
#include "server/collision/collision_world.h"
#include "server/loop/snapshot.h"

namespace igms {

struct FaultInjection {
  double drop = 0.0;      // fraction of states not published
  double burst_ms = 0.0;  // every second, no states for this long
  double delay_us = 0.0;  // every state published this much later
  bool any() const { return drop > 0 || burst_ms > 0 || delay_us > 0; }
};

// What the status reports about the published states.
struct PublishStats {
  explicit PublishStats(const Model& model) : limits(model) {}
  double last_sim_time = 0.0;
  int64_t collisions = 0;              // published states in collision
  double first_collision = -1.0;       // s
  double min_distance = 1e9;           // m, over the run
  std::vector<double> step_times_us;   // since the status last drained them
  JointLimitReport limits;             // joints beyond their position limits, over the run
  ContactSolveStats solve;             // the contact solver's totals, as of the newest state
  int solve_sweeps_max = 0;            // since the status last drained them: the most sweeps in a solve,
  double solve_residual_max = 0.0;     // the largest final residual (m/s),
  double solve_slip_angle_max = 0.0;   // the largest angle a slipping friction left from opposing its slip (rad),
  double solve_linearised_angle_max = 0.0;  // and the largest a friction kept on the linearised cone left (rad)
  int64_t candidates_dropped = 0;      // as of the newest state (snapshot.h)
  int64_t proxy_substep_limited = 0;
};

// One LCM datagram's payload at most (LCM 1.3.1 sends a message as one UDP datagram; a larger one
// fragments, and a lost fragment loses the state).
constexpr int kMaxDatagramBytes = 65499;

// A state message sized for the model (every link's pose, kMaxHands hand rows).
robot_state_t sizedStateMessage(const Model& model);
// "" when the model's state fits one datagram; else why not, naming the sizes.
std::string stateTooLarge(const Model& model, const std::string& scene);

class StatePublisher {
 public:
  StatePublisher(bus::SignedPublisher& bus, const Model& model, const GeometryModel& geometry, FaultInjection faults,
                 bool quiet);
  void publish(const Snapshot& s);
  PublishStats& stats() { return stats_; }

 private:
  void fill(const Snapshot& s);
  void checkCollisions(const Snapshot& s);
  bool faultDrops();

  bus::SignedPublisher& bus_;
  const std::string state_channel_{channels::kRobotState}, truth_channel_{channels::kRobotStateTruth};  // no allocation per message
  CollisionWorld world_;
  FaultInjection faults_;
  bool quiet_;
  robot_state_t msg_;
  std::vector<uint8_t> buffer_;
  PublishStats stats_;
  std::mt19937 rng_{12345};
  std::uniform_real_distribution<double> uniform_{0.0, 1.0};
  double fault_epoch_;
};

}  // namespace igms
