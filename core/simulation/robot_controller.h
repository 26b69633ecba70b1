// One robot's controller in an environment: the trajectory it follows (the
// scene's nominal one, then the C2 resume trajectory generation builds from
// the new state when a hand lets go) and the law that follows it:
//   computed torque (the paper's): inverse dynamics of qdd_ref + kp (q_ref - q) + kd (qd_ref - v),
//     which the step's first evaluation resolves (CoupledInputs::inverse_dynamics); without a
//     trajectory the robot is passive;
//   PD (a legged robot standing): tau = kp (q_ref - q) + kd (qd_ref - v) on its joints, toward the
//     trajectory or, without one, its initial posture, taken implicitly by the step.
// It works on its own tree's slice of the environment's vectors. Built once (allocates); the
// per-step calls do not allocate.
#pragma once

#include "core/scene/resolved_scene.h"
#include "core/simulation/coupled_dynamics.h"
#include "core/simulation/edited_trajectory.h"
#include "core/trajectory/piecewise_polynomial.h"

namespace igms {

class RobotController {
 public:
  // Throws SceneError for a trajectory the robot cannot follow.
  RobotController(const Model& model, const ResolvedScene& resolved, int robot);

  // Back to the scene's start: its nominal trajectory from time 0, its edited motion cleared.
  void reset(const VectorX& q0);
  // A hand let go at time t in state (q, v, qdd): a quintic from there to the goal. \return true
  // when one started.
  bool replan(double t, const VectorX& q, const VectorX& v, const VectorX& qdd);
  // This step's command at time t, state (q, v), holding (a hand acts) or not: the computed-torque
  // acceleration into qdd_cmd (its dofs), or the PD's gains and references into pd (its dofs).
  void command(double t, const VectorX& q, const VectorX& v, bool holding, VectorX& qdd_cmd, VectorX& pd_kp,
               VectorX& pd_kd, VectorX& pd_q, VectorX& pd_v);

  ControllerKind kind() const { return kind_; }
  // Has a trajectory to follow (the nominal or a resume one).
  bool active() const { return active_ != nullptr; }
  // Inverse dynamics drives it this step (computed torque with a trajectory).
  bool inverseDynamics() const { return kind_ == ControllerKind::ComputedTorque && active(); }
  double holdDamping() const { return hold_damping_; }
  const ModelPart& part() const { return part_; }
  const PiecewisePolynomial& nominal() const { return nominal_; }
  const VectorX& goal() const { return goal_; }
  // Replace the nominal trajectory (its coordinates), restarted at time t.
  void setNominalTrajectory(double t, const std::vector<double>& times, const std::vector<VectorX>& points);
  // Its executed motion, the paper's edited trajectory (edited_trajectory.h), and the step's sample of
  // it (every kPeriod, and whenever `force`d: a start, a replan).
  const EditedTrajectory& edited() const { return edited_; }
  void record(double t, const VectorX& q, bool force) { edited_.sample(t, q, force); }

 private:
  const Model& model_;
  const ModelPart part_;
  const ControllerKind kind_;
  const VectorX kp_, kd_;       // its nv
  const double hold_damping_;
  PiecewisePolynomial nominal_, resume_;
  const PiecewisePolynomial* active_ = nullptr;
  double active_offset_ = 0.0;  // the active trajectory is evaluated at t - active_offset_
  VectorX goal_, posture_;      // its nq
  VectorX q_ref_, qd_ref_, qdd_ref_, qs_, vs_, as_, zero_;
  EditedTrajectory edited_;
};

}  // namespace igms
