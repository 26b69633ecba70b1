#include "core/simulation/simulation.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/joint_damping.h"
#include "core/dynamics/rnea.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/scene/trajectory_file.h"
#include "core/trajectory/cartesian_line.h"

namespace igms {

namespace {
constexpr double kRecordPeriod = 0.01;          // s
constexpr int kRecordCapacity = 60000;          // 10 minutes at 100 Hz
constexpr double kDivergedSpeed = 1e4;          // rad/s or m/s: no robot moves like this
constexpr double kResumeSpeed = 1.0;            // rad/s, mean speed of a resume trajectory
constexpr int kResumeGapSteps = 20;             // steps without any input: a gap
constexpr int64_t kResumeSeqJump = 100;         // a client's seq jumping this far: a gap (jitter stays below)
constexpr double kResumeRamp = 0.1;             // s to bring the coupling back in after a gap
}  // namespace

Simulation::Simulation(ResolvedScene resolved)
    : resolved_(std::move(resolved)), scene_(resolved_.scene), model_(resolved_.model) {
  const Model& m = *model_;
  data_ = std::make_unique<Data>(m);
  dynamics_ = std::make_unique<CoupledDynamics>(m, scene_);
  scratch_ = std::make_unique<IntegratorScratch<CoupledEvaluation>>(m, *dynamics_);
  const VectorX& q0 = resolved_.q0;
  // Nominal trajectory.
  switch (scene_.trajectory.kind) {
    case TrajectorySpec::Kind::None: break;
    case TrajectorySpec::Kind::JointWaypoints:
      for (const auto& p : scene_.trajectory.waypoints)
        if (p.size() != m.nq) throw SceneError(scene_.source + ": trajectory waypoint size differs from nq");
      nominal_ = PiecewisePolynomial::clampedCubicSpline(scene_.trajectory.times, scene_.trajectory.waypoints);
      break;
    case TrajectorySpec::Kind::CartesianLine: {
      CartesianLine line;
      line.frame = m.frameIndex(scene_.trajectory.frame);
      if (line.frame < 0)
        throw SceneError(scene_.source + ": trajectory.frame: unknown link '" + scene_.trajectory.frame + "'");
      line.target = scene_.trajectory.target;
      line.duration = scene_.trajectory.duration;
      try {
        nominal_ = cartesianLineTrajectory(m, q0, line);
      } catch (const std::runtime_error& e) {
        throw SceneError(scene_.source + ": trajectory: " + e.what());
      }
      break;
    }
  }
  resume_ = PiecewisePolynomial(m.nq, 1);
  resume_.setQuintic(0.0, 1.0, q0, resolved_.v0, resolved_.v0, q0, resolved_.v0, resolved_.v0);  // sizes the storage once
  link_poses_.resize(m.frames.size());
  edited_t_.assign(kRecordCapacity, 0.0);
  edited_q_ = MatrixX::Zero(kRecordCapacity, m.nq);
  q_ref_ = qd_ref_ = qdd_ref_ = VectorX::Zero(m.nq);
  qdd_cmd_ = zero_ = VectorX::Zero(m.nv);
  reset();
}

Simulation::~Simulation() = default;

void Simulation::reset() {
  q_ = resolved_.q0;
  v_ = resolved_.v0;
  q_good_ = q_;
  v_good_ = v_;
  qdd_ = VectorX::Zero(model_->nv);
  tau_ = VectorX::Zero(model_->nv);
  t_ = 0.0;
  steps_ = 0;
  interacting_ = false;
  diverged_ = false;
  divergence_.clear();
  forces_clamped_ = 0;
  active_ = nominal_.empty() ? nullptr : &nominal_;
  active_offset_ = 0.0;
  goal_ = resolved_.q0;
  if (!nominal_.empty()) nominal_.finalPoint(goal_);
  edited_count_ = 0;
  next_record_t_ = 0.0;
  coupling_ = Coupling{};
  setGains(scene_.push.k_p, scene_.pull.k, scene_.pull.b);
  last_input_seq_ = -1;
  last_input_client_ = -1;
  steps_without_input_ = 0;
  stall_noted_ = false;
  resume_ramps_ = 0;
  record(true);
}

void Simulation::setState(double t, const VectorX& q, const VectorX& v, const VectorX& qdd, bool interacting) {
  q_ = q;
  v_ = v;
  qdd_ = qdd;
  q_good_ = q;
  v_good_ = v;
  t_ = t;
  interacting_ = interacting;
  diverged_ = false;
  last_input_seq_ = -1;  // a re-based copy does not know the server's gaps
  steps_without_input_ = 0;
  stall_noted_ = false;
  coupling_.scale = 1.0;
}

void Simulation::setNominalTrajectory(const std::vector<double>& times, const std::vector<VectorX>& points) {
  nominal_ = PiecewisePolynomial::clampedCubicSpline(times, points);
  nominal_.finalPoint(goal_);
  active_ = &nominal_;
  active_offset_ = t_;
}

void Simulation::setGains(double push_k_p, double pull_k, double pull_b) {
  coupling_.push_k_p = push_k_p;
  coupling_.pull_k = pull_k;
  coupling_.pull_b = pull_b;
}

// The step's inputs: the coupling (from the validated haptic input) and the
// controller torque; a quintic resume trajectory when an interaction ends.
void Simulation::computeControl(const InteractionInput* in) {
  const Model& m = *model_;
  const bool user = in && in->mode != InteractionMode::None &&
                    ((in->mode == InteractionMode::Push && scene_.push.enabled) ||
                     (in->mode == InteractionMode::Pull && scene_.pull.enabled));
  outcome_ = StepOutcome{};
  if (in) {  // every consumed input is named in the state, whatever its mode
    outcome_.input_seq = in->seq;
    outcome_.input_client = in->client;
  }
  coupling_.mode = user ? in->mode : InteractionMode::None;
  // The resume ramp (see simulation.h).
  // A gap between inputs (not before the first one): steps without any, or the client's seq jumping.
  const bool gap = stall_noted_ ||
                   (last_input_seq_ >= 0 &&
                    (steps_without_input_ >= kResumeGapSteps ||
                     (in && in->client == last_input_client_ && in->seq - last_input_seq_ > kResumeSeqJump)));
  if (user && gap) {
    coupling_.scale = 0.0;
    ++resume_ramps_;
  }
  // A stall waits for the next step that has an input: the first steps after one often have none fresh
  // (the last arrived before the stop), and the queued inputs that follow run on in seq.
  if (in) stall_noted_ = false;
  if (coupling_.scale < 1.0) coupling_.scale = std::min(1.0, coupling_.scale + scene_.dt / kResumeRamp);
  if (in) {
    last_input_seq_ = in->seq;
    last_input_client_ = in->client;
    steps_without_input_ = 0;
  } else {
    ++steps_without_input_;
  }
  if (user) {
    coupling_.tip = in->tip_position;
    coupling_.tip_velocity = in->tip_velocity;
    coupling_.tip_radius = in->tip_radius;
    coupling_.contact_frame = in->contact_frame;
    coupling_.attach_frame = in->attach_frame >= 0 ? in->attach_frame : resolved_.pull_frame;
    coupling_.attach_point = in->attach_frame >= 0 ? in->attach_point : scene_.pull.point;
  }
  if (user && !interacting_) interacting_ = true;
  if (!user && interacting_) {
    // Generation resumes from the new state: a quintic from (q, v, qdd) to the goal.
    interacting_ = false;
    if (active_) {
      const double remaining = active_ == &nominal_ ? nominal_.endTime() - (t_ - active_offset_) : 0.0;
      const double distance = (goal_ - q_).cwiseAbs().maxCoeff();
      const double T = std::max({remaining, 0.5, 1.875 * distance / kResumeSpeed});
      resume_.setQuintic(t_, T, q_, v_, qdd_, goal_, zero_, zero_);
      active_ = &resume_;
      active_offset_ = 0.0;
      outcome_.replanned = true;
    }
  }
  outcome_.mode = coupling_.mode;
  hold_rate_ = (interacting_ && active_) ? scene_.hold_damping : 0.0;
  if (!active_) {
    tau_.setZero();  // no trajectory: a passive robot
  } else if (interacting_) {
    // Hold: gravity and Coriolis compensation (and joint damping); the
    // dynamics add the hold damping. The user's force moves the robot.
    tau_ = bias(m, *data_, q_, v_);
    if (scene_.joint_damping) tau_ += jointDamping(m).cwiseProduct(v_);
  } else {
    active_->evaluate(t_ - active_offset_, q_ref_, qd_ref_, qdd_ref_);
    qdd_cmd_ = qdd_ref_ + resolved_.kp.cwiseProduct(q_ref_ - q_) + resolved_.kd.cwiseProduct(qd_ref_ - v_);
    tau_ = rnea(m, *data_, q_, v_, qdd_cmd_);  // computed torque by inverse dynamics
    if (scene_.joint_damping) tau_ += jointDamping(m).cwiseProduct(v_);
  }
  if (m.floating_base) tau_.head<6>().setZero();  // the base is not actuated
}

bool Simulation::step(const InteractionInput* input) {
  if (diverged_) return false;
  computeControl(input);
  const CoupledInputs inputs{tau_, coupling_, hold_rate_};
  CoupledDynamics::Bound f = dynamics_->bind(inputs);
  const bool ok = integrateStep(scene_.integrator, *model_, f, q_, v_, scene_.dt, *scratch_);
  // What the step reports is the evaluation at its start state.
  const CoupledEvaluation& start = scratch_->start;
  qdd_ = start.qdd;
  outcome_.force_on_robot = start.coupling.on_robot;
  outcome_.force_point = start.coupling.point;
  outcome_.clamped = start.coupling.clamped && start.coupling.coupled;
  if (outcome_.clamped) ++forces_clamped_;
  t_ += scene_.dt;
  ++steps_;
  if (!ok || !checkFinite()) {
    if (divergence_.empty())
      divergence_ = "diverged at t = " + std::to_string(t_) + " s: the system matrix became singular";
    diverged_ = true;
    q_ = q_good_;
    v_ = v_good_;
    return false;
  }
  q_good_ = q_;
  v_good_ = v_;
  record(outcome_.replanned);
  return true;
}

bool Simulation::checkFinite() {
  const Model& m = *model_;
  if (q_.allFinite() && v_.allFinite() && qdd_.allFinite() && v_.cwiseAbs().maxCoeff() < kDivergedSpeed) return true;
  int worst = 0;
  for (int k = 0; k < m.nv; ++k)
    if (!std::isfinite(v_[k]) || std::abs(v_[k]) > std::abs(v_[worst])) worst = k;
  divergence_ = "diverged at t = " + std::to_string(t_) + " s (step " + std::to_string(steps_) +
                "): joint '" + dofName(m, worst) + "' velocity " + std::to_string(v_[worst]) +
                "; last good state kept. A stiffer coupling needs the linearly_implicit integrator or a smaller dt.";
  return false;
}

void Simulation::record(bool force) {
  if (!force && t_ + 1e-12 < next_record_t_) return;
  if (edited_count_ >= kRecordCapacity) return;
  edited_t_[static_cast<size_t>(edited_count_)] = t_;
  edited_q_.row(edited_count_) = q_.transpose();
  ++edited_count_;
  next_record_t_ = t_ + kRecordPeriod;
}

const std::vector<SE3>& Simulation::linkPoses() {
  forwardKinematics(*model_, *data_, q_);
  for (size_t f = 0; f < link_poses_.size(); ++f) link_poses_[f] = data_->oMf[f];
  return link_poses_;
}

void Simulation::saveEditedTrajectory(const std::string& path) const {
  std::vector<double> times;
  std::vector<VectorX> rows;
  double last_t = -1.0;
  for (int k = 0; k < edited_count_; ++k) {
    if (edited_t_[static_cast<size_t>(k)] <= last_t + 1e-9) continue;  // a spline needs increasing times
    last_t = edited_t_[static_cast<size_t>(k)];
    times.push_back(last_t);
    rows.push_back(edited_q_.row(k).transpose());
  }
  if (times.size() < 2) throw std::runtime_error(path + ": fewer than two samples recorded");
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write the edited trajectory");
  out << trajectoryFileText(scene_.source, model_->joint_name, times, rows);
  if (!out) throw std::runtime_error(path + ": cannot write the edited trajectory");
}

std::vector<std::string> Simulation::activeComponents() const {
  std::vector<std::string> c;
  c.push_back(model_->floating_base ? "floating_base" : "fixed_base");
  if (!nominal_.empty()) c.push_back("trajectory");
  if (!nominal_.empty()) c.push_back("computed_torque");
  if (scene_.push.enabled) c.push_back("push");
  if (scene_.pull.enabled) c.push_back("pull");
  if (scene_.needsCollision()) c.push_back("collision");
  if (scene_.joint_damping) c.push_back("joint_damping");
  c.push_back(std::string("integrator:") + integratorName(scene_.integrator));
  return c;
}

}  // namespace igms
