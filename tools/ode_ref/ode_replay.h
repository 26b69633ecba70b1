// ODE as the independent reference on recorded sessions and torque sequences.
//
// replayOnOde: the scene of a recorded igms session is rebuilt in ODE and
// driven open-loop by what the log says igms applied at each step: the
// controller's joint torques (tau), the user's force at its world point on the
// link the input named (push: contact_link, pull: attach_link), the model's
// joint damping, and the controller's hold damping -c H v while the user
// interacts (the one force the log does not hold: computed here from ODE's
// own state with igms's inertia matrix). ODE's trajectory is compared with the
// recorded one and returned as robot_state_t, the format igms logs.
//
// Open loop means errors grow with the robot's own instability: the
// deviation is reported per simulated second, so its growth is visible.
// With tracking, ODE also gets the scene's own PD gains on its deviation from
// the recorded run, tau += H(q) (kp (q_rec - q) + kd (v_rec - v)), as igms's
// computed-torque controller would have applied on ODE's state: the deviation
// stays bounded, and the size of that correction against tau measures how
// much the two simulators disagree.
#pragma once

#include <string>
#include <vector>

#include "igms/robot_state_t.hpp"
#include "igms/session_info_t.hpp"
#include "tools/eventlog/event_log.h"
#include "tools/ode_ref/ode_robot.h"

namespace igms {

struct OdeReplayResult {
  bool ok = false;
  std::string error;
  int64_t steps = 0;
  double dt = 0.0;
  double q_max = 0.0, q_rms = 0.0;       // joint-space deviation from the recorded run, rad (m for prismatic)
  double link_max = 0.0;                 // largest link-origin position deviation, m
  std::vector<double> link_max_by_second;  // the same within each simulated second
  double correction_rms = 0.0, tau_rms = 0.0;  // tracking torque against the recorded tau, N m
  double wall_seconds = 0.0;             // ODE's stepping alone
  session_info_t info;
  std::vector<robot_state_t> states;     // ODE's run: seq 0 (initial) onwards
};

// base_dir resolves the scene's relative paths, as for igms-replay resim.
OdeReplayResult replayOnOde(const std::vector<log::Event>& events, const OdeSettings& settings,
                            const std::string& base_dir = ".", bool tracking = false);

// A torque sequence: row k holds tau (size nv) applied over [k h, (k+1) h).
// Returns the states after each step (seq 1..), with the initial one first.
std::vector<robot_state_t> runTorquesOnOde(const Model& model, const VectorX& q0, const VectorX& v0,
                                           const std::vector<VectorX>& torques, double h,
                                           const OdeSettings& settings);

// An LCM log of the states (with the session info first when given), readable
// by igms-replay export and the plotting scripts.
void writeStateLog(const std::string& path, const session_info_t* info, const std::vector<robot_state_t>& states);

}  // namespace igms
