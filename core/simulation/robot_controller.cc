#include "core/simulation/robot_controller.h"

#include <algorithm>
#include <stdexcept>

#include "core/trajectory/cartesian_line.h"

namespace igms {

namespace {
constexpr double kResumeSpeed = 1.0;  // rad/s, mean speed of a resume trajectory
}  // namespace

RobotController::RobotController(const Model& model, const ResolvedScene& resolved, int robot)
    : model_(model),
      part_(model.parts[static_cast<size_t>(resolved.robots[static_cast<size_t>(robot)].part)]),
      kind_(resolved.scene.robots[static_cast<size_t>(resolved.robots[static_cast<size_t>(robot)].spec)].controller),
      kp_(resolved.robots[static_cast<size_t>(robot)].kp),
      kd_(resolved.robots[static_cast<size_t>(robot)].kd),
      hold_damping_(resolved.scene.robots[static_cast<size_t>(resolved.robots[static_cast<size_t>(robot)].spec)].hold_damping) {
  const Scene& scene = resolved.scene;
  const RobotSpec& spec = scene.robots[static_cast<size_t>(resolved.robots[static_cast<size_t>(robot)].spec)];
  const int nq = part_.nq();
  // Its own joint names (the environment's carry the robot's name in front) for the saved file.
  const std::string prefix = spec.name.empty() ? "" : spec.name + "/";
  std::vector<std::string> joints;
  for (int i = part_.body_begin; i < part_.body_end; ++i) joints.push_back(model.joint_name[i].substr(prefix.size()));
  edited_ = EditedTrajectory(part_.q_begin, nq, std::move(joints), scene.source);
  posture_ = resolved.q0.segment(part_.q_begin, nq);
  const std::string at = spec.name.empty() ? "" : "robots[" + std::to_string(robot) + "].";
  switch (spec.trajectory.kind) {
    case TrajectorySpec::Kind::None: break;
    case TrajectorySpec::Kind::JointWaypoints:
      for (const auto& p : spec.trajectory.waypoints)
        if (p.size() != nq) throw SceneError(scene.source + ": " + at + "trajectory waypoint size differs from nq");
      nominal_ = PiecewisePolynomial::clampedCubicSpline(spec.trajectory.times, spec.trajectory.waypoints);
      break;
    case TrajectorySpec::Kind::CartesianLine: {
      // Inverse kinematics on the environment model: the robot's own tree moves its frame alone.
      CartesianLine line;
      line.frame = model.frameIndex((spec.name.empty() ? "" : spec.name + "/") + spec.trajectory.frame);
      if (line.frame < 0 || model.partOfFrame(line.frame) != resolved.robots[static_cast<size_t>(robot)].part)
        throw SceneError(scene.source + ": " + at + "trajectory.frame: unknown link '" + spec.trajectory.frame + "'");
      line.target = spec.trajectory.target;
      line.duration = spec.trajectory.duration;
      try {
        const PiecewisePolynomial whole = cartesianLineTrajectory(model, resolved.q0, line);
        nominal_ = part_.q_begin == 0 && nq == model.nq ? whole : whole.slice(part_.q_begin, nq);
      } catch (const std::runtime_error& e) {
        throw SceneError(scene.source + ": " + at + "trajectory: " + e.what());
      }
      break;
    }
  }
  const VectorX v0 = resolved.v0.segment(part_.dof_begin, part_.nv());
  resume_ = PiecewisePolynomial(nq, 1);
  if (nq == part_.nv()) resume_.setQuintic(0.0, 1.0, posture_, v0, v0, posture_, v0, v0);  // sizes the storage once
  q_ref_ = qd_ref_ = qdd_ref_ = qs_ = VectorX::Zero(nq);
  vs_ = as_ = zero_ = VectorX::Zero(part_.nv());
  reset(resolved.q0);
}

void RobotController::reset(const VectorX& q0) {
  edited_.clear();
  active_ = nominal_.empty() ? nullptr : &nominal_;
  active_offset_ = 0.0;
  goal_ = q0.segment(part_.q_begin, part_.nq());
  if (!nominal_.empty()) nominal_.finalPoint(goal_);
}

bool RobotController::replan(double t, const VectorX& q, const VectorX& v, const VectorX& qdd) {
  if (!active_) return false;
  // Generation resumes from the new state: a quintic from (q, v, qdd) to the goal.
  qs_ = q.segment(part_.q_begin, part_.nq());
  vs_ = v.segment(part_.dof_begin, part_.nv());
  as_ = qdd.segment(part_.dof_begin, part_.nv());
  const double remaining = active_ == &nominal_ ? nominal_.endTime() - (t - active_offset_) : 0.0;
  const double distance = (goal_ - qs_).cwiseAbs().maxCoeff();
  const double T = std::max({remaining, 0.5, 1.875 * distance / kResumeSpeed});
  resume_.setQuintic(t, T, qs_, vs_, as_, goal_, zero_, zero_);
  active_ = &resume_;
  active_offset_ = 0.0;
  return true;
}

void RobotController::command(double t, const VectorX& q, const VectorX& v, bool holding, VectorX& qdd_cmd,
                              VectorX& pd_kp, VectorX& pd_kd, VectorX& pd_q, VectorX& pd_v) {
  const int d0 = part_.dof_begin, nv = part_.nv(), q0 = part_.q_begin, nq = part_.nq();
  if (kind_ == ControllerKind::ComputedTorque) {
    if (active_ && !holding) {
      active_->evaluate(t - active_offset_, q_ref_, qd_ref_, qdd_ref_);
      qdd_cmd.segment(d0, nv) = qdd_ref_ + kp_.cwiseProduct(q_ref_ - q.segment(q0, nq)) +
                                kd_.cwiseProduct(qd_ref_ - v.segment(d0, nv));
    } else if (holding) {
      qdd_cmd.segment(d0, nv).setZero();  // the hold is inverse dynamics of zero: b(q, v)
    }
    return;
  }
  // PD toward the trajectory (a fixed base: coordinates and dofs alike) or the posture; a hand's
  // hold keeps the PD on the posture it had.
  if (active_ && !holding) active_->evaluate(t - active_offset_, q_ref_, qd_ref_, qdd_ref_);
  else if (!active_) {
    q_ref_ = posture_;
    qd_ref_.setZero();
  }
  for (int i = part_.body_begin; i < part_.body_end; ++i) {
    if (model_.joint_type[i] == JointType::Floating) continue;
    const int k = model_.v_index[i], c = model_.q_index[i] - q0;
    pd_kp[k] = kp_[k - d0];
    pd_kd[k] = kd_[k - d0];
    pd_q[k] = q_ref_[c];
    pd_v[k] = c < qd_ref_.size() && nq == nv ? qd_ref_[c] : 0.0;
  }
}

void RobotController::setNominalTrajectory(double t, const std::vector<double>& times, const std::vector<VectorX>& points) {
  nominal_ = PiecewisePolynomial::clampedCubicSpline(times, points);
  nominal_.finalPoint(goal_);
  active_ = &nominal_;
  active_offset_ = t;
}

}  // namespace igms
