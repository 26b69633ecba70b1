// A scene and a device script, run in-process: the client's logic (device,
// push and pull, rendering) driving the server's step in lockstep, with no
// network and no clock. Deterministic; used to design and test the paper's
// experiments, and by the demo's summary.
#pragma once

#include <string>
#include <vector>

#include "core/model/model.h"
#include "core/scene/scene.h"

namespace igms {

struct ScenarioSample {
  double t;
  std::vector<double> q;   // the environment's coordinates (ScenarioResult::q_columns names them)
  int mode;
  Vector3 force_on_robot, ee;
  Vector3 rendered = Vector3::Zero();  // the force the hand was rendered this step (the device's)
  Vector3 tip, proxy;      // the device's tip and its proxy, scene frame (zero without a device)
  double min_obstacle_distance;
  bool in_collision;
  int contacts;            // contact points at the step's start
  double max_penetration;  // m, their deepest overlap (0: none)
  int solver_sweeps;       // the contact solve's sweeps this step (0: no contact)
  double solver_residual;  // m/s: its last sweep's largest velocity change (0: exact, or no contact)
};

// The contact solve over the run (core/contact/contact_solver.h, ContactSolveStats).
struct ScenarioSolveStats {
  int64_t solves = 0;               // steps with contact
  int64_t unconverged = 0;          // solves that stopped at the sweep limit
  int max_sweeps = 0;               // the most sweeps one solve took
  int64_t polish_rounds = 0;        // the active-set solve's dense solves, over the run
  double max_residual = 0.0;        // m/s, the largest residual a solve ended with
  int64_t warm_dropped = 0;         // warm starts that cost more than a cold one
  int64_t restitution_scaled = 0;   // impacts whose restitution was scaled down to add no energy
  int64_t energy_capped = 0;        // solves whose impulses were scaled down to add no energy
  int64_t position_unconverged = 0;  // position corrections that stopped at the sweep limit
  int64_t near_rebuilds = 0;        // the detection's broad phases (its list of near pairs rebuilt)
  int64_t candidates_dropped = 0;   // candidate pairs beyond the detection's buffers (contacts missed)
  int64_t polish_cycles = 0;
  int64_t linearised_exact = 0, linearised = 0, linearised_failed = 0;  // islands answered on the linearised cone
  double max_linearised_angle = 0.0;  // rad: a kept polytope friction's largest angle off against its slip        // active-set islands whose guess came back to the one two rounds before
  int64_t slips_unturned = 0;       // active-set answers whose slipping friction kept the sweeps' direction
  int64_t large_solves = 0;         // active-set islands too large for the dense solve, by conjugate gradients
  int64_t large_iterations = 0;     // and their iterations
  double max_slip_angle = 0.0;      // rad, the largest angle an active-set answer left between a slipping
                                    // friction and the reverse of its slip
};

struct ScenarioResult {
  std::vector<ScenarioSample> samples;   // every step
  std::vector<std::string> q_columns;   // a name per coordinate of q (coordinateNames)
  std::vector<std::string> bodies;       // the free bodies' names, in q order
  int max_contacts = 0;                  // contact points in a step, at most
  double max_penetration = 0.0;          // m, the deepest overlap of any step
  int64_t collision_steps = 0;           // with obstacles other than the wall
  int64_t collision_steps_all = 0;       // with anything, the wall included
  double first_collision = -1.0;         // s
  std::string first_collision_what;      // "link3 hits obstacle"
  double min_distance = 1e9;             // robot vs obstacles other than the wall... see below
  double min_distance_excluding_goal = 1e9;  // ignoring the obstacle named "wall" (the goal is to touch it)
  double reached_wall_time = -1.0;       // s when the end-effector first came within reach_tolerance of the target
  Vector3 final_ee = Vector3::Zero();
  double max_user_force = 0.0;           // N, |force rendered to the user|
  double max_force_step = 0.0;           // N, the rendered force's largest change in one cycle
  // The hand's proxy (core/interaction/proxy.h): its deepest overlap with anything (m; it stays on
  // surfaces), and how far the device got behind it while it touched something (m).
  double max_proxy_penetration = 0.0;
  double max_device_behind_proxy = 0.0;
  double max_robot_force = 0.0;          // N, |force applied to the robot|
  std::vector<std::pair<double, double>> interactions;  // [start, end] s of each push or pull
  std::vector<int> interaction_modes;
  ScenarioSolveStats solve;
  bool diverged = false;
};

// Runs `seconds` of the scene with the device script (scripted:FILE) at the
// scene's rate. save_edited: write the executed trajectory there (optional).
// device_limits: render within the device's force and per-cycle step, as igms-haptic does (without:
// the force the laws give, unbounded, which the paper's experiments compare).
ScenarioResult runScenario(const Scene& scene, const std::string& device_script, double seconds,
                           const std::string& save_edited = "", double reach_tolerance = 0.01,
                           bool device_limits = false);

}  // namespace igms
