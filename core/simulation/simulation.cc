#include "core/simulation/simulation.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "core/dynamics/forward_dynamics.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/scene/trajectory_file.h"

namespace igms {

namespace {
constexpr double kDivergedSpeed = 1e4;          // rad/s or m/s: no robot moves like this
}  // namespace

namespace {

// The environment's contact model: its geoms (the model's links and free bodies, the solid
// obstacles, the ground), the scene's materials; null when nothing can touch.
std::unique_ptr<ContactModel> contactModelOf(const ResolvedScene& r) {
  const Scene& s = r.scene;
  if (!s.hasContact()) return nullptr;
  std::vector<Material> materials;
  for (const std::string& name : r.material_names) materials.push_back(s.materials.at(name));
  auto cm = std::make_unique<ContactModel>(*r.model, *r.geometry, materials, s.contact);
  if (cm->empty()) return nullptr;
  return cm;
}

}  // namespace

Simulation::Simulation(ResolvedScene resolved)
    : resolved_(std::move(resolved)), scene_(resolved_.scene), model_(resolved_.model), placed_(*resolved_.geometry) {
  const Model& m = *model_;
  data_ = std::make_unique<Data>(m);
  contact_model_ = contactModelOf(resolved_);
  dynamics_ = std::make_unique<CoupledDynamics>(m, scene_, resolved_.q0, contact_model_.get());
  if (contact_model_) {
    detection_ = std::make_unique<ContactDetection>(*contact_model_);
    contacts_ = ContactSet(contact_model_->capacity());
  }
  applied_acceleration_ = dynamics_->hasContacts() && scene_.integrator == IntegratorKind::LinearlyImplicit;
  dynamics_->reportAppliedAcceleration(applied_acceleration_);
  v_start_ = VectorX::Zero(m.nv);
  v_implicit_ = VectorX::Zero(m.nv);
  q_start_ = VectorX::Zero(m.nq);
  scratch_ = std::make_unique<IntegratorScratch<CoupledEvaluation>>(m, *dynamics_);
  for (size_t k = 0; k < resolved_.robots.size(); ++k) {
    controllers_.push_back(std::make_unique<RobotController>(m, resolved_, static_cast<int>(k)));
    any_pd_ = any_pd_ || controllers_.back()->kind() == ControllerKind::Pd;
  }
  robot_held_.assign(controllers_.size(), 0);
  touch_ = scene_.push.enabled;
  if (touch_)
    for (HandTrack& h : hands_) h.proxy = Proxy(geometry(), scene_.push.friction);
  hold_.reserve(controllers_.size());
  uncommanded_.reserve(controllers_.size());
  link_poses_.resize(m.frames.size());
  link_velocities_.resize(m.frames.size());
  qdd_cmd_ = VectorX::Zero(m.nv);
  pd_kp_ = pd_kd_ = pd_q_ = pd_v_ = VectorX::Zero(m.nv);
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
  diverged_ = false;
  divergence_.clear();
  forces_clamped_ = 0;
  for (auto& c : controllers_) c->reset(resolved_.q0);
  contacts_.n = 0;
  dynamics_->resetContacts();
  gains_ = CouplingGains{};
  setGains(scene_.push.k_p, scene_.pull.k, scene_.pull.b);
  setRotationalGains(scene_.pull.k_rot, scene_.pull.b_rot);
  ncouplings_ = 0;
  for (HandTrack& h : hands_) {
    h.restart(-1);
    h.letGo();
    h.proxy.release();
  }
  std::fill(robot_held_.begin(), robot_held_.end(), 0);
  stall_noted_ = false;
  resume_ramps_ = 0;
  for (auto& c : controllers_) c->record(t_, q_, true);
}

void Simulation::setState(double t, const VectorX& q, const VectorX& v, const VectorX& qdd, bool interacting) {
  q_ = q;
  v_ = v;
  qdd_ = qdd;
  q_good_ = q;
  v_good_ = v;
  t_ = t;
  diverged_ = false;
  // A re-based copy does not know the server's gaps; its hands' proxies go on from where they were.
  for (HandTrack& h : hands_) h.restart(h.client());
  std::fill(robot_held_.begin(), robot_held_.end(), interacting ? 1 : 0);
  stall_noted_ = false;
  contacts_.n = 0;
  dynamics_->resetContacts();
}

bool Simulation::hasTrajectory() const {
  for (const auto& c : controllers_)
    if (!c->nominal().empty()) return true;
  return false;
}

void Simulation::saveEdited(int robot, const std::string& path) const {
  if (robot < 0 || robot >= robots()) EditedTrajectory().save(path);  // says there is no such robot
  else this->robot(robot).edited().save(path);
}

void Simulation::setNominalTrajectory(int robot, const std::vector<double>& times, const std::vector<VectorX>& points) {
  if (robot < 0 || robot >= robots()) throw std::runtime_error(scene_.source + ": no robot " + std::to_string(robot));
  const int nq = controllers_[static_cast<size_t>(robot)]->part().nq();
  for (const VectorX& p : points)
    if (p.size() != nq)
      throw std::runtime_error("a point has " + std::to_string(p.size()) + " coordinates, the robot " +
                               std::to_string(nq));
  controllers_[static_cast<size_t>(robot)]->setNominalTrajectory(t_, times, points);
}

void Simulation::setGains(double push_k_p, double pull_k, double pull_b) {
  gains_.push_k_p = push_k_p;
  gains_.push_b = scene_.push.b;
  gains_.pull_k = pull_k;
  gains_.pull_b = pull_b;
}

void Simulation::setRotationalGains(double k_rot, double b_rot) {
  gains_.pull_k_rot = k_rot;
  gains_.pull_b_rot = b_rot;
}

// The client's track, or a new one in place of the hand quiet for longest.
HandTrack& Simulation::track(int32_t client) {
  for (HandTrack& h : hands_)
    if (h.client() == client) return h;
  HandTrack* pick = &hands_[0];
  for (HandTrack& h : hands_) {
    if (h.client() < 0) {
      pick = &h;
      break;
    }
    if (h.stepsWithoutInput() > pick->stepsWithoutInput()) pick = &h;
  }
  pick->restart(client);
  pick->proxy.release();
  if (stall_noted_) pick->noteStall();
  return *pick;
}

// The step's inputs: one coupling per hand (from the validated haptic inputs, in client-id order),
// the holds (a quintic resume trajectory when the last interaction on a robot ends) and the
// controllers' commands.
void Simulation::coupleHands(const HandInputs& inputs) {
  // Client-id order (a handful: insertion sort, no allocation); equal ids keep their order.
  const int n = std::min(inputs.n, kMaxHands);
  for (int i = 0; i < n; ++i) {
    int j = i;
    while (j > 0 && inputs.in[static_cast<size_t>(order_[static_cast<size_t>(j - 1)])].client >
                        inputs.in[static_cast<size_t>(i)].client) {
      order_[static_cast<size_t>(j)] = order_[static_cast<size_t>(j - 1)];
      --j;
    }
    order_[static_cast<size_t>(j)] = i;
  }
  for (HandTrack& h : hands_) h.tick(scene_.dt);  // every hand's ramp runs on whether or not it has an input
  bool any_user = false;
  ncouplings_ = 0;
  for (int k = 0; k < n; ++k) {
    const InteractionInput& in = inputs.in[static_cast<size_t>(order_[static_cast<size_t>(k)])];
    HandOutcome& ho = outcome_.hands[static_cast<size_t>(outcome_.nhands++)];
    ho = HandOutcome{};
    ho.client = in.client;  // every consumed input is named in the state, whatever its mode
    ho.input_seq = in.seq;
    const bool user = (in.mode == InteractionMode::Push && scene_.push.enabled) ||
                      (in.mode == InteractionMode::Pull && scene_.pull.enabled);
    HandTrack& h = track(in.client);
    if (h.take(in.seq, user, scene_.dt)) ++resume_ramps_;
    // The hand's proxy follows its tip whatever the mode (free while it pulls), against the start state.
    if (touch_) h.proxy.update(geometry(), placed_, in.tip_position, in.tip_radius, in.mode == InteractionMode::Pull);
    if (!user) continue;
    if (!any_user) outcome_.mode = in.mode;
    any_user = true;
    ho.mode = in.mode;
    Coupling& c = couplings_[static_cast<size_t>(ncouplings_++)];
    c.hand = in;
    c.gains = gains_;
    c.scale = h.scale();
    coupling_hand_[static_cast<size_t>(ncouplings_ - 1)] = &h;
    c.contact_frame = -1;  // the push acts where the server's proxy rests, on something that moves
    c.push_shape = nullptr;
    if (in.mode == InteractionMode::Push && touch_) {
      // What the proxy rests on; else the moving shape nearest it, which the step's later stages may reach
      // (its depth is then the tip's own, as without a proxy).
      const int k = h.proxy.deepest(geometry(), in.tip_position, true);
      const int geom = k >= 0 ? h.proxy.touch(k).geom
                              : h.proxy.nearestMovable(geometry(), placed_, in.tip_radius, in.tip_radius);
      if (geom >= 0) {
        const GeometryObject& g = geometry().object(geom);
        c.contact_frame = g.frame;
        c.push_shape = g.shape;
        c.push_placement = g.placement;
        c.proxy = h.proxy.position();
      }
    }
    c.pull_frame = in.attach_frame >= 0 ? in.attach_frame : resolved_.pull_frame;
    c.pull_point = in.attach_frame >= 0 ? in.attach_point : scene_.pull.point;
    c.robot = h.holdRobot(robotOfFrame(c.actsOn()));
    c.carried_force = h.carriedForce(c.actsOn());
    c.carried_torque = h.carriedTorque(c.actsOn());
    c.tip_rotation = in.tip_orientation.toRotationMatrix();
    c.attach_rotation = in.attach_orientation.toRotationMatrix();
  }
  if (n > 0) {
    stall_noted_ = false;
    outcome_.input_seq = outcome_.hands[0].input_seq;
    outcome_.input_client = outcome_.hands[0].client;
  }
}

int Simulation::robotOfFrame(int frame) const {
  for (size_t r = 0; r < controllers_.size(); ++r) {
    const ModelPart& part = controllers_[r]->part();
    if (frame >= part.frame_begin && frame < part.frame_end) return static_cast<int>(r);
  }
  return -1;
}

void Simulation::decideHolds() {
  // A hand holds the robot it acts on alone; the others follow their trajectories. When the last
  // hand on a robot lets go, generation resumes for it from the new state: a quintic from (q, v, qdd)
  // to its goal.
  for (size_t r = 0; r < controllers_.size(); ++r) {
    bool held = false;
    for (int i = 0; i < ncouplings_; ++i) held = held || couplings_[static_cast<size_t>(i)].robot == static_cast<int>(r);
    if (!held && robot_held_[r] && controllers_[r]->replan(t_, q_, v_, qdd_)) outcome_.replanned = true;
    robot_held_[r] = held;
  }
}

// The torque is inverse dynamics at the start state, which the step's first evaluation computes
// in the pass that gives the plant's bias (CoupledInputs::inverse_dynamics, set in step): it adds
// the joint damping's D v and leaves floating joints unactuated. While a hand acts, it is the
// hold's gravity and Coriolis compensation (the dynamics add the hold damping: the users' forces
// move the robot); otherwise the computed torque of qdd_cmd_. A PD robot's torque is the dynamics'
// (CoupledInputs::pd), a passive robot's none.
void Simulation::commandRobots() {
  inverse_dynamics_ = false;
  following_ = false;
  hold_.clear();
  uncommanded_.clear();
  for (size_t r = 0; r < controllers_.size(); ++r) {
    RobotController* c = controllers_[r].get();
    const ModelPart& part = c->part();
    const bool held = robot_held_[r] != 0;
    const bool holds = held && c->active();
    if (holds && c->kind() == ControllerKind::ComputedTorque)
      hold_.push_back(DofRange{part.dof_begin, part.dof_end, c->holdDamping()});
    if (c->inverseDynamics()) {
      inverse_dynamics_ = true;
      following_ = following_ || !held;
    } else {
      uncommanded_.push_back(DofRange{part.dof_begin, part.dof_end, 0.0});
    }
    c->command(t_, q_, v_, held, qdd_cmd_, pd_kp_, pd_kd_, pd_q_, pd_v_);
  }
  if (!inverse_dynamics_) tau_.setZero();  // no trajectory: passive robots (and PD robots' torque is the dynamics')
}

bool Simulation::step(const InteractionInput* input) {
  one_.clear();
  if (input) one_.add(*input);
  return step(one_);
}

void Simulation::placeGeometry(const HandInputs& hands) {
  if (dynamics_->hasContacts() || (touch_ && hands.n > 0)) dynamics_->placeGeometry(q_, geometry(), placed_);
}

bool Simulation::step(const HandInputs& hands) {
  if (diverged_) return false;
  // The stages (docs/architecture.md): the geometry placed and the contacts found at the start state,
  // the controls and the hands, then the dynamics (integrateStep: the coupled dynamics, their contact
  // solve and the configuration update).
  outcome_.restart();
  placeGeometry(hands);
  if (detection_) detection_->detect(placed_, contacts_);
  coupleHands(hands);
  decideHolds();
  commandRobots();
  // A held robot's share of qdd_cmd is zero (RobotController::command), which gives its b(q, v) alone;
  // with every robot held, inverse dynamics is the bias alone (one force set, not two).
  CoupledInputs inputs{tau_, couplings_.data(), ncouplings_, inverse_dynamics_, following_ ? &qdd_cmd_ : nullptr};
  inputs.hold = &hold_;
  if (!uncommanded_.empty()) inputs.uncommanded = &uncommanded_;
  if (any_pd_) inputs.pd = JointPd{&pd_kp_, &pd_kd_, &pd_q_, &pd_v_};
  if (detection_) inputs.contacts = &contacts_;
  CoupledDynamics::StepEvaluator f = dynamics_->bind(inputs);
  const bool implicit = scene_.integrator == IntegratorKind::LinearlyImplicit;  // applied_acceleration_ implies it
  if (implicit) {
    v_start_ = v_;
    q_start_ = q_;
  }
  const bool ok = integrateStep(scene_.integrator, *model_, f, q_, v_, scene_.dt, *scratch_);
  // What the step reports is the evaluation at its start state, but for the hands' forces under the
  // linearly-implicit step: that step takes their springs at its end, and it reports what it applied.
  const CoupledEvaluation& start = scratch_->start;
  if (applied_acceleration_) qdd_ = (v_ - v_start_) / scene_.dt;
  else qdd_ = start.qdd;
  const std::array<CouplingForce, kMaxHands>* couplings = &start.couplings;
  if (implicit && ok) {
    implicitEndVelocity();
    dynamics_->appliedCouplings(start, v_start_, v_implicit_, scene_.dt, applied_couplings_);
    couplings = &applied_couplings_;
  }
  // The couplings are in the order of the interacting hands among outcome_.hands.
  int c = 0;
  for (int k = 0; k < outcome_.nhands; ++k) {
    HandOutcome& ho = outcome_.hands[static_cast<size_t>(k)];
    if (ho.mode == InteractionMode::None) continue;
    const CouplingForce& u = (*couplings)[static_cast<size_t>(c++)];
    if (c == 1) outcome_.force_point = u.applied.point;  // the first interacting hand's (zero when it touches nothing)
    if (!u.coupled) continue;
    coupling_hand_[static_cast<size_t>(c - 1)]->gave(u.frame, u.applied.force.norm(), u.applied.torque.norm());
    ho.applied = u.applied;
    outcome_.force_on_robot += u.applied.force;
    outcome_.torque_on_robot += u.applied.torque;
    outcome_.clamped = outcome_.clamped || u.applied.clamped;
  }
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
  for (auto& c : controllers_) c->record(t_, q_, outcome_.replanned);
  return true;
}

void Simulation::implicitEndVelocity() {
  v_implicit_ = v_;
  if (!dynamics_->hasContacts()) return;  // v is the end velocity, in the coordinates the step solved in
  // With contact a floating joint's linear velocity took h w x v explicitly before the solve
  // (worldVelocityStep) and was carried into the turned frame after it (integrateContactStep): both
  // undone, so it is the v+ of the step's linear system, in the start frame.
  const Model& m = *model_;
  for (int i = 0; i < m.nb; ++i) {
    if (m.joint_type[i] != JointType::Floating) continue;
    const int iq = m.q_index[i], iv = m.v_index[i];
    const Eigen::Quaterniond r0(q_start_[iq + 3], q_start_[iq + 4], q_start_[iq + 5], q_start_[iq + 6]);
    const Eigen::Quaterniond r1(q_[iq + 3], q_[iq + 4], q_[iq + 5], q_[iq + 6]);
    const Vector3 in_start = (r0.normalized().conjugate() * r1.normalized()) * Vector3(v_.segment<3>(iv));
    v_implicit_.segment<3>(iv) =
        in_start - scene_.dt * Vector3(v_start_.segment<3>(iv + 3)).cross(Vector3(v_start_.segment<3>(iv)));
  }
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

const Proxy* Simulation::proxyOf(int32_t client) const {
  if (!touch_) return nullptr;
  for (const HandTrack& h : hands_)
    if (h.client() == client) return &h.proxy;
  return nullptr;
}

int64_t Simulation::proxySubstepLimited() const {
  int64_t n = 0;
  if (touch_)
    for (const HandTrack& h : hands_) n += h.proxy.substepLimited();
  return n;
}

const std::vector<SE3>& Simulation::linkPoses() {
  forwardKinematics(*model_, *data_, q_);
  for (size_t f = 0; f < link_poses_.size(); ++f) link_poses_[f] = data_->oMf[f];
  return link_poses_;
}

const std::vector<Motion>& Simulation::linkVelocities() {
  bodyKinematics(*model_, *data_, q_);
  frameVelocities(*model_, *data_, v_, link_velocities_);
  return link_velocities_;
}

std::vector<std::string> Simulation::activeComponents() const {
  std::vector<std::string> c;
  if (!controllers_.empty()) c.push_back(model_->floating_base ? "floating_base" : "fixed_base");
  if (hasTrajectory()) c.push_back("trajectory");
  bool computed = false;
  for (const auto& r : controllers_) computed |= !r->nominal().empty() && r->kind() == ControllerKind::ComputedTorque;
  if (computed) c.push_back("computed_torque");
  if (any_pd_) c.push_back("pd");
  if (controllers_.size() > 1) c.push_back("robots:" + std::to_string(controllers_.size()));
  if (!scene_.bodies.empty()) c.push_back("free_bodies:" + std::to_string(scene_.bodies.size()));
  if (scene_.ground.enabled) c.push_back("ground");
  if (dynamics_->hasContacts()) c.push_back("contact");
  if (scene_.push.enabled) c.push_back("push");
  if (scene_.pull.enabled) c.push_back("pull");
  if (scene_.needsCollision()) c.push_back("collision");
  if (scene_.joint_damping) c.push_back("joint_damping");
  c.push_back(std::string("integrator:") + integratorName(scene_.integrator));
  return c;
}

}  // namespace igms
