// Simulation: the paper's "Steps for Interactive Simulation", one step at a time.
//
//   IF there is haptic input (push or pull, from one hand or several):
//     the controller holds gravity and Coriolis compensation plus damping, and
//     each hand's force enters the forward dynamics, summed: U_E = J^T c (push,
//     eq. 3) or tau = J^T F (pull, eq. 4; F a force and, for a device with an
//     orientation, a torque), computed here from the device state against the
//     exact robot state;
//   ELSE:
//     the trajectory point to follow, computed-torque control by inverse
//     dynamics (PD on the error), accelerations by forward dynamics (eq. 2);
//   update the state (the scene's integrator).
// When an interaction ends, a new C2 (quintic) trajectory starts from the
// current q, v, qdd toward the goal (each robot's: robot_controller.h). In an
// environment (several robots, free bodies, the ground, solid obstacles) the
// step also finds the contacts at its start and solves them with the velocity
// update (core/contact/contact_solver.h). When an interaction comes back after a
// gap (the loop stopped for over 20 ms, 20 steps without an input from that
// client, or its seq jumping by more than 100: a stalled server, a stalled
// client, inputs lost), that hand's coupling is brought back in over 100 ms instead
// of as one step: the push the hand stored up meanwhile reaches the robot as
// a ramp. The ramp starts from the force (and torque) the hand gave the same
// link the step before the gap, not from zero: a hand that leaned on a box
// through a stall of the loop goes on holding it, and only what it added
// comes back over the ramp. The rule reads the inputs and the states' timing only, so
// re-simulating a log reproduces it. The executed motion is recorded as the
// edited trajectory.
//
// Built once from a Scene (allocates); step() never allocates.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/contact/contact_detection.h"
#include "core/contact/contact_model.h"
#include "core/integrate/integrators.h"
#include "core/interaction/proxy.h"
#include "core/scene/resolved_scene.h"
#include "core/simulation/coupled_dynamics.h"
#include "core/simulation/hand_input.h"
#include "core/simulation/hand_track.h"
#include "core/simulation/robot_controller.h"
#include "core/trajectory/piecewise_polynomial.h"

namespace igms {

class Simulation {
 public:
  // Throws SceneError / ModelError / std::runtime_error with a clear message.
  explicit Simulation(ResolvedScene resolved);
  explicit Simulation(const Scene& scene) : Simulation(resolveScene(scene)) {}
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  void reset();
  // Puts the robot in a given state without touching the trajectory: q, v and
  // the last step's qdd at time t, interacting or not. A haptic client's local
  // model re-bases itself on each server state this way. No allocation.
  void setState(double t, const VectorX& q, const VectorX& v, const VectorX& qdd, bool interacting);
  // One step of scene.dt with the inputs of every hand this step consumes
  // (none: no haptic input). Each hand's coupling is its own (its resume
  // ramp too); their forces add up.
  // \return false when the state diverged (see divergenceReport()); the state
  // then stays at the last good one and further steps do nothing.
  bool step(const HandInputs& inputs);
  // One hand, or none (null).
  bool step(const InteractionInput* input);

  const Model& model() const { return *model_; }
  const Scene& scene() const { return scene_; }
  const ResolvedScene& resolved() const { return resolved_; }
  double time() const { return t_; }
  int64_t steps() const { return steps_; }
  const VectorX& q() const { return q_; }
  const VectorX& v() const { return v_; }
  const VectorX& qdd() const { return qdd_; }
  const VectorX& tau() const { return tau_; }
  const StepOutcome& outcome() const { return outcome_; }
  bool diverged() const { return diverged_; }
  const std::string& divergenceReport() const { return divergence_; }
  int64_t forcesClamped() const { return forces_clamped_; }
  int pullFrame() const { return resolved_.pull_frame; }
  // World poses of every URDF link at the current state.
  const std::vector<SE3>& linkPoses();
  // Every link's velocity at the current state, world axes (frameVelocities): its origin's and its angular.
  const std::vector<Motion>& linkVelocities();
  // The geometry world (every shape the contact, the hands' proxies and the obstacle monitor use), and
  // its placement at the last step's start (placed only when the step needs it: contact or a hand).
  const GeometryModel& geometry() const { return *resolved_.geometry; }
  const GeometryData& placedGeometry() const { return placed_; }
  // A hand's proxy (null with push off, or no such client yet).
  const Proxy* proxyOf(int32_t client) const;
  // Cycles in which a hand's proxy ran out of its substep budget (it catches up the next), every hand's.
  int64_t proxySubstepLimited() const;
  // The robots, in scene order (a scene of free bodies has none), each with its controller: its goal
  // (its coordinates), its nominal trajectory, its edited motion (robot_controller.h).
  int robots() const { return static_cast<int>(controllers_.size()); }
  const RobotController& robot(int r) const { return *controllers_[static_cast<size_t>(r)]; }
  // The robot whose links include this frame (-1: a free body's, or no frame).
  int robotOfFrame(int frame) const;
  // Some robot has a trajectory to follow.
  bool hasTrajectory() const;
  // Robot r's edited motion, written as a scene-loadable waypoint file (EditedTrajectory::save). Throws
  // std::runtime_error naming the path: no such robot (a scene of free bodies), too short, not written.
  void saveEdited(int robot, const std::string& path) const;
  // Replace robot r's nominal trajectory (its coordinates; restarts it at the current time). Throws
  // std::runtime_error for no such robot or a point of another size.
  void setNominalTrajectory(int robot, const std::vector<double>& times, const std::vector<VectorX>& points);

  // The contacts at the last step's start, with the impulses its solve gave them (empty without contact).
  const ContactSet& contacts() const { return contacts_; }
  const ContactSolveStats& contactStats() const { return dynamics_->contactStats(); }
  // Its detection (null: no contact): how often its list of near pairs was rebuilt, candidates dropped.
  const ContactDetection* contactDetection() const { return detection_.get(); }
  bool hasContacts() const { return dynamics_->hasContacts(); }
  const ContactModel* contactModel() const { return contact_model_.get(); }
  // Interaction gains (push k_p, pull k, pull b; the 6-D pull's k_rot, b_rot), e.g. from a SET_GAINS command.
  void setGains(double push_k_p, double pull_k, double pull_b);
  void setRotationalGains(double k_rot, double b_rot);
  // Resume ramps so far: interactions brought back in over kResumeRamp after a gap.
  int64_t resumeRamps() const { return resume_ramps_; }
  // The loop was stopped (over kStallGapUs between steps): if the next step that has an input interacts,
  // however many steps later, it starts a resume ramp. The server notes it from its clock, a re-simulation from the states' utime, with this one threshold.
  void noteStall() {
    stall_noted_ = true;
    for (auto& h : hands_) h.noteStall();
  }
  static constexpr int64_t kStallGapUs = 20000;


  // Components this scene uses ("trajectory", "push", "pull", "collision", ...).
  std::vector<std::string> activeComponents() const;

 private:
  HandTrack& track(int32_t client);
  // The first stage: the bodies and the geometry placed at the start state, when contact or a hand
  // needs them (the dynamics' start evaluation reuses the bodies' poses).
  void placeGeometry(const HandInputs& inputs);
  // The control stage of a step, in order (step() calls them): each hand's input into its coupling
  // (in client-id order), which robot each hand holds (a hand holds the robot whose link it pushes or
  // pulls; a replan for one let go), and each robot's command (the hold's, or its trajectory's or PD's).
  void coupleHands(const HandInputs& inputs);
  void decideHolds();
  void commandRobots();
  bool checkFinite();

  const ResolvedScene resolved_;
  const Scene& scene_;                  // resolved_.scene
  std::shared_ptr<const Model> model_;  // resolved_.model
  std::unique_ptr<Data> data_;
  std::unique_ptr<ContactModel> contact_model_;  // null without any pair that can touch
  std::unique_ptr<CoupledDynamics> dynamics_;
  std::unique_ptr<IntegratorScratch<CoupledEvaluation>> scratch_;
  // The step's inputs, set by its control stage and passed to the dynamics.
  std::array<Coupling, kMaxHands> couplings_;
  int ncouplings_ = 0;
  std::array<int, kMaxHands> order_{};  // the step's inputs by client id
  CouplingGains gains_;                 // the gains every coupling takes
  std::array<HandTrack, kMaxHands> hands_;
  std::array<HandTrack*, kMaxHands> coupling_hand_{};  // each coupling's hand, this step
  bool touch_ = false;                  // push on: the hands' proxies touch the geometry
  GeometryData placed_;                 // the geometry at the step's start
  std::unique_ptr<ContactDetection> detection_;  // null without contact
  ContactSet contacts_;                 // the step's: found at its start, their impulses from its solve
  std::vector<char> robot_held_;            // per robot: a hand acts on it (an environment's holds)
  HandInputs one_;                      // step(const InteractionInput*)'s set
  bool inverse_dynamics_ = false;      // some robot is driven by inverse dynamics this step (commandRobots)
  bool following_ = false;              // and some such robot follows its trajectory (is not held)
  std::vector<std::unique_ptr<RobotController>> controllers_;  // one per robot, in scene order
  std::vector<DofRange> hold_, uncommanded_;
  VectorX pd_kp_, pd_kd_, pd_q_, pd_v_;
  bool any_pd_ = false;
  bool applied_acceleration_ = false;   // qdd is (v+ - v) / h (contact with the linearly-implicit step)
  VectorX v_start_;                      // the step's start velocity (the implicit step's forces, qdd)
  std::array<CouplingForce, kMaxHands> applied_couplings_;  // the hands' forces the implicit step applied
  VectorX q_start_, v_implicit_;         // the implicit step's start q, and its v+ as its linear system saw it
  void implicitEndVelocity();
  VectorX q_, v_, qdd_, tau_;
  VectorX qdd_cmd_;
  double t_ = 0.0;
  int64_t steps_ = 0;
  bool diverged_ = false;
  std::string divergence_;
  int64_t forces_clamped_ = 0;
  bool stall_noted_ = false;       // a stall no input has followed yet (a new hand's track starts with it)
  int64_t resume_ramps_ = 0;
  StepOutcome outcome_;
  std::vector<SE3> link_poses_;
  std::vector<Motion> link_velocities_;
  VectorX q_good_, v_good_;     // last finite state
};

}  // namespace igms
