#include "core/simulation/simulation.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <stdexcept>

#include "core/dynamics/external_force.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/rnea.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/model_io/model_loader.h"
#include "core/trajectory/cartesian_line.h"

namespace igms {

namespace {
constexpr double kRecordPeriod = 0.01;          // s
constexpr int kRecordCapacity = 60000;          // 10 minutes at 100 Hz
constexpr double kDivergedSpeed = 1e4;          // rad/s or m/s: no robot moves like this
constexpr double kResumeSpeed = 1.0;            // rad/s, mean speed of a resume trajectory
}  // namespace

// Forward dynamics under the controller torque (held over the step) and the
// user's coupling (device state held over the step), for the integrators.
struct Simulation::Evaluator {
  Evaluator(const Model& m, const Scene& s)
      : model(m), scene(s), data(m), tau(VectorX::Zero(m.nv)), tau_total(VectorX::Zero(m.nv)),
        F(VectorX::Zero(m.nv)), fext(static_cast<size_t>(m.nb)), KJ(3, m.nv), J(6, m.nv) {}

  const Model& model;
  const Scene& scene;
  Data data;
  VectorX tau, tau_total, F;
  std::vector<Force> fext;
  Eigen::Matrix<double, 3, Eigen::Dynamic> KJ;
  Matrix6X J;

  // The coupling, held over the step.
  InteractionMode mode = InteractionMode::None;
  Vector3 tip = Vector3::Zero(), tip_velocity = Vector3::Zero();
  double tip_radius = 0.01;
  int contact_frame = -1, attach_frame = -1;
  Vector3 attach_point = Vector3::Zero();
  double push_k_p = 0, pull_k = 0, pull_b = 0;
  double hold_rate = 0.0;  // 1/s: while the user interacts, -hold_rate H v (every joint's velocity decays alike)

  // Results of the last accel(): the coupling's force and its linearisation.
  bool coupled = false;
  int coupled_frame = -1;
  Vector3 coupled_point = Vector3::Zero();  // link frame
  Vector3 coupling_force = Vector3::Zero(), force_point = Vector3::Zero();
  bool clamped = false;
  Matrix3 K = Matrix3::Zero(), B = Matrix3::Zero();

  void couple(const VectorX& v) {
    coupled = false;
    coupling_force.setZero();
    if (mode == InteractionMode::Push) {
      TipContact best;
      int best_frame = -1;
      for (size_t f = 0; f < model.frames.size(); ++f) {
        if (contact_frame >= 0 && static_cast<int>(f) != contact_frame) continue;
        const Frame& fr = model.frames[f];
        if (fr.body < 0) continue;  // fixed to the world: nothing to push
        const SE3 oMf = framePose(model, data, static_cast<int>(f));
        for (const auto& shape : fr.collisions) {
          const TipContact c = tipContact(shape, oMf * shape.placement, tip, tip_radius);
          if (c.touching && c.depth > best.depth) {
            best = c;
            best_frame = static_cast<int>(f);
          }
        }
      }
      if (best_frame < 0) return;
      const PushForce p = pushForce(best, push_k_p, scene.push.max_force);
      coupled = true;
      coupled_frame = best_frame;
      coupled_point = framePose(model, data, best_frame).inverse().act(p.point);
      coupling_force = p.on_link;
      force_point = p.point;
      clamped = p.clamped;
      K = p.clamped ? Matrix3::Zero() : Matrix3(push_k_p * best.normal * best.normal.transpose());
      B.setZero();
    } else if (mode == InteractionMode::Pull && attach_frame >= 0) {
      const Vector3 x = framePose(model, data, attach_frame).act(attach_point);
      pointJacobian(model, data, attach_frame, attach_point, J);
      const Vector3 xd = J.topRows<3>() * v;
      const PullForce p =
          pullForce(pull_k, pull_b, scene.pull.max_stretch, scene.pull.max_force, tip, tip_velocity, x, xd);
      coupled = true;
      coupled_frame = attach_frame;
      coupled_point = attach_point;
      coupling_force = p.on_robot;
      force_point = x;
      clamped = p.clamped;
      K = (p.stretch_capped || p.clamped) ? Matrix3::Zero() : Matrix3(pull_k * Matrix3::Identity());
      B = p.clamped ? Matrix3::Zero() : Matrix3(pull_b * Matrix3::Identity());
    }
  }

  void accel(const VectorX& q, const VectorX& v, VectorX& qdd) {
    bodyKinematics(model, data, q);
    clearExternalForces(fext);
    couple(v);
    if (coupled) addPointForce(model, data, PointForce{coupled_frame, coupled_point, coupling_force}, fext);
    tau_total = tau;
    if (scene.joint_damping) for (int k = 0; k < model.nv; ++k) tau_total[k] -= model.damping[k] * v[k];
    if (!forwardDynamics(model, data, q, v, tau_total, coupled ? &fext : nullptr)) {
      qdd.setConstant(std::numeric_limits<double>::quiet_NaN());  // caught by the divergence guard
      return;
    }
    F = tau_total - data.bias;  // = H qdd
    qdd = data.qdd;
    if (hold_rate > 0.0) {
      // -c H v: H^-1 of it is exactly -c v.
      F.noalias() -= hold_rate * (data.H * v);
      qdd -= hold_rate * v;
    }
  }
  const MatrixX& H() const { return data.H; }
  const VectorX& force() const { return F; }

  void addStiffness(MatrixX& A, VectorX& rhs, const VectorX& v, double h) {
    if (scene.joint_damping) A.diagonal() += h * Eigen::Map<const VectorX>(model.damping.data(), model.nv);
    if (hold_rate > 0.0) A += (h * hold_rate) * data.H;
    if (!coupled) return;
    pointJacobian(model, data, coupled_frame, coupled_point, J);
    // A += J^T (h B + h^2 K) J, rhs -= h^2 J^T K J v, written out: no temporaries.
    const Matrix3 M = h * B + h * h * K;
    KJ.noalias() = M * J.topRows<3>();
    const Vector3 KJv = (h * h) * (K * (J.topRows<3>() * v));
    for (int c = 0; c < model.nv; ++c) {
      rhs[c] -= J.col(c).head<3>().dot(KJv);
      for (int r = 0; r < model.nv; ++r) A(r, c) += J.col(r).head<3>().dot(KJ.col(c));
    }
  }
};


Simulation::Simulation(const Scene& scene) : scene_(scene) {
  model_ = std::make_unique<const Model>(loadModel(scene_.model_path, scene_.build));
  const Model& m = *model_;
  data_ = std::make_unique<Data>(m);
  eval_ = std::make_unique<Evaluator>(m, scene_);
  scratch_ = std::make_unique<IntegratorScratch>(m);
  q0_ = scene_.q0.size() ? scene_.q0 : neutralConfiguration(m);
  v0_ = scene_.v0.size() ? scene_.v0 : VectorX::Zero(m.nv);
  if (q0_.size() != m.nq)
    throw SceneError(scene_.source + ": initial.q has " + std::to_string(q0_.size()) + " entries, the model needs " +
                     std::to_string(m.nq));
  if (v0_.size() != m.nv)
    throw SceneError(scene_.source + ": initial.v has " + std::to_string(v0_.size()) + " entries, the model needs " +
                     std::to_string(m.nv));
  normalizeConfiguration(m, q0_);
  auto perJoint = [&](const VectorX& given, double scalar, const char* key) {
    if (!given.size()) return VectorX(VectorX::Constant(m.nv, scalar));
    if (given.size() != m.nv)
      throw SceneError(scene_.source + ": controller." + key + " needs " + std::to_string(m.nv) + " entries");
    return given;
  };
  kp_ = perJoint(scene_.kp, scene_.kp_scalar, "kp");
  kd_ = perJoint(scene_.kd, scene_.kd_scalar, "kd");
  if (scene_.pull.enabled) {
    const std::string link = scene_.pull.link.empty() ? m.frames.back().name : scene_.pull.link;
    pull_frame_ = m.frameIndex(link);
    if (pull_frame_ < 0) throw SceneError(scene_.source + ": interaction.pull.link: unknown link '" + link + "'");
  }
  if (m.floating_base && scene_.trajectory.kind != TrajectorySpec::Kind::None)
    throw SceneError(scene_.source + ": trajectory: a floating-base robot has no joint-space trajectory to follow");
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
        nominal_ = cartesianLineTrajectory(m, q0_, line);
      } catch (const std::runtime_error& e) {
        throw SceneError(scene_.source + ": trajectory: " + e.what());
      }
      break;
    }
  }
  resume_ = PiecewisePolynomial(m.nq, 1);
  resume_.setQuintic(0.0, 1.0, q0_, v0_, v0_, q0_, v0_, v0_);  // sizes the storage once
  link_poses_.resize(m.frames.size());
  edited_t_.assign(kRecordCapacity, 0.0);
  edited_q_ = MatrixX::Zero(kRecordCapacity, m.nq);
  q_ref_ = qd_ref_ = qdd_ref_ = VectorX::Zero(m.nq);
  reset();
}

Simulation::~Simulation() = default;

void Simulation::reset() {
  q_ = q0_;
  v_ = v0_;
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
  goal_ = q0_;
  if (!nominal_.empty()) nominal_.finalPoint(goal_);
  edited_count_ = 0;
  next_record_t_ = 0.0;
  eval_->push_k_p = scene_.push.k_p;
  eval_->pull_k = scene_.pull.k;
  eval_->pull_b = scene_.pull.b;
  record(true);
}

void Simulation::setNominalTrajectory(const std::vector<double>& times, const std::vector<VectorX>& points) {
  nominal_ = PiecewisePolynomial::clampedCubicSpline(times, points);
  nominal_.finalPoint(goal_);
  active_ = &nominal_;
  active_offset_ = t_;
}

void Simulation::setGains(double push_k_p, double pull_k, double pull_b) {
  eval_->push_k_p = push_k_p;
  eval_->pull_k = pull_k;
  eval_->pull_b = pull_b;
}

void Simulation::computeControl(const InteractionInput* in) {
  const Model& m = *model_;
  Evaluator& e = *eval_;
  const bool user = in && in->mode != InteractionMode::None &&
                    ((in->mode == InteractionMode::Push && scene_.push.enabled) ||
                     (in->mode == InteractionMode::Pull && scene_.pull.enabled));
  outcome_ = StepOutcome{};
  if (in) {  // every consumed input is named in the state, whatever its mode
    outcome_.input_seq = in->seq;
    outcome_.input_client = in->client;
  }
  e.mode = user ? in->mode : InteractionMode::None;
  if (user) {
    e.tip = in->tip_position;
    e.tip_velocity = in->tip_velocity;
    e.tip_radius = in->tip_radius;
    e.contact_frame = in->contact_frame;
    e.attach_frame = in->attach_frame >= 0 ? in->attach_frame : pull_frame_;
    e.attach_point = in->attach_frame >= 0 ? in->attach_point : scene_.pull.point;
  }
  if (user && !interacting_) interacting_ = true;
  if (!user && interacting_) {
    // Generation resumes from the new state: a quintic from (q, v, qdd) to the goal.
    interacting_ = false;
    if (active_) {
      const double remaining = active_ == &nominal_ ? nominal_.endTime() - (t_ - active_offset_) : 0.0;
      const double distance = (goal_ - q_).cwiseAbs().maxCoeff();
      const double T = std::max({remaining, 0.5, 1.875 * distance / kResumeSpeed});
      scratch_->k1.setZero();
      resume_.setQuintic(t_, T, q_, v_, qdd_, goal_, scratch_->k1, scratch_->k1);
      active_ = &resume_;
      active_offset_ = 0.0;
      outcome_.replanned = true;
    }
  }
  outcome_.mode = e.mode;
  e.hold_rate = (interacting_ && active_) ? scene_.hold_damping : 0.0;
  if (!active_) {
    e.tau.setZero();  // no trajectory: a passive robot
  } else if (interacting_) {
    // Hold: gravity and Coriolis compensation (and joint damping); the
    // evaluator adds the hold damping. The user's force moves the robot.
    e.tau = bias(m, *data_, q_, v_);
    if (scene_.joint_damping) e.tau += Eigen::Map<const VectorX>(m.damping.data(), m.nv).cwiseProduct(v_);
  } else {
    active_->evaluate(t_ - active_offset_, q_ref_, qd_ref_, qdd_ref_);
    scratch_->qdd = qdd_ref_ + kp_.cwiseProduct(q_ref_ - q_) + kd_.cwiseProduct(qd_ref_ - v_);
    e.tau = rnea(m, *data_, q_, v_, scratch_->qdd);  // computed torque by inverse dynamics
    if (scene_.joint_damping) e.tau += Eigen::Map<const VectorX>(m.damping.data(), m.nv).cwiseProduct(v_);
  }
  if (m.floating_base) e.tau.head<6>().setZero();  // the base is not actuated
}

bool Simulation::step(const InteractionInput* input) {
  if (diverged_) return false;
  computeControl(input);
  Evaluator& e = *eval_;
  const double h = scene_.dt;
  bool ok = true;
  switch (scene_.integrator) {
    case IntegratorKind::SemiImplicitEuler: stepSemiImplicitEuler(*model_, e, q_, v_, h, *scratch_); break;
    case IntegratorKind::Rk4: stepRk4(*model_, e, q_, v_, h, *scratch_); break;
    case IntegratorKind::LinearlyImplicit: ok = stepLinearlyImplicit(*model_, e, q_, v_, h, *scratch_); break;
  }
  // The step's reported acceleration and force: at the start state (what the
  // paper plots), from the first evaluation.
  qdd_ = scene_.integrator == IntegratorKind::Rk4 ? scratch_->k1 : scratch_->qdd;
  tau_ = e.tau;
  outcome_.force_on_robot = e.coupling_force;
  outcome_.force_point = e.force_point;
  outcome_.device_force = -e.coupling_force;
  outcome_.clamped = e.clamped && e.coupled;
  if (outcome_.clamped) ++forces_clamped_;
  t_ += h;
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
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write the edited trajectory");
  out << "# Edited trajectory from scene " << scene_.source << ", " << edited_count_ << " samples.\n"
      << "# Load it as a scene's nominal trajectory: trajectory: {kind: file, file: THIS_FILE}\n"
      << "waypoints:\n";
  out << std::setprecision(17);
  int written = 0;
  double last_t = -1.0;
  for (int k = 0; k < edited_count_; ++k) {
    if (edited_t_[static_cast<size_t>(k)] <= last_t + 1e-9) continue;  // a spline needs increasing times
    last_t = edited_t_[static_cast<size_t>(k)];
    out << "  - {t: " << last_t << ", q: [";
    for (int j = 0; j < model_->nq; ++j) out << (j ? ", " : "") << edited_q_(k, j);
    out << "]}\n";
    ++written;
  }
  if (written < 2) throw std::runtime_error(path + ": fewer than two samples recorded");
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
