#include "core/simulation/coupled_dynamics.h"

#include <algorithm>
#include <cstring>
#include <limits>

#include "core/dynamics/crba.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/dynamics/joint_damping.h"
#include "core/dynamics/ltdl.h"
#include "core/dynamics/rnea.h"
#include "core/geometry/point_query.h"
#include "core/geometry/tip_contact.h"
#include "core/interaction/pull.h"
#include "core/interaction/push.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/kinematics/jacobian.h"
#include "core/model/ancestor_runs.h"
#include "core/model/configuration.h"

namespace igms {

CoupledDynamics::CoupledDynamics(const Model& m, const Scene& s, const VectorX& q_reference, const ContactModel* contacts)
    : model_(m), scene_(s), limits_(m, q_reference, s.joint_limits), free_bodies_(m), data_(m),
      tau_total_(VectorX::Zero(m.nv)),
      fext_(static_cast<size_t>(m.nb)), KJ_(6, m.nv), J_(6, m.nv) {
  for (Matrix6X& J : coupling_J_) J.setZero(6, m.nv);
  for (int i = 0; i < m.nb; ++i)
    if (m.joint_type[i] == JointType::Floating) floating_.push_back(DofRange{m.v_index[i], m.v_index[i] + 6, 0.0});
  // The free bodies' blocks of H (at any pose: crbaUpper writes a free body's from its inertia alone)
  // and their factors.
  Data at(m);
  free_inertia_ = crba(m, at, q_reference);
  free_factors_ = free_inertia_;
  for (int i = 0; i < m.nb; ++i) {
    if (m.joint_type[i] != JointType::Floating || !m.children[i].empty()) continue;
    const int b = free_inertia_.blockOf(m.v_index[i]);
    if (free_inertia_.blockEnd(b) - free_inertia_.blockBegin(b) != 6) continue;
    if (ltdlFactorBlock(m.dof_parent, m.dof_run_start, free_factors_, at.diag, b) < 0) free_blocks_.push_back(b);
  }
  if (contacts && !contacts->empty()) {
    contacts_ = contacts;
    solver_ = std::make_unique<ContactSolver>(m, *contacts);
  }
}

const ContactSolveStats& CoupledDynamics::contactStats() const {
  static const ContactSolveStats kNone;
  return solver_ ? solver_->stats() : kNone;
}

void CoupledDynamics::resetContacts() {
  if (solver_) solver_->resetWarmStart();
}

void CoupledDynamics::constrain(const CoupledInputs& in, const VectorX& v0, double h, const TreeMatrix* factored,
                                VectorX& v, VectorX& v_position) {
  solver_->solve(data_, factored ? *factored : data_.Hfact, h, v0, *in.contacts, v, v_position);
}

CoupledEvaluation CoupledDynamics::makeEvaluation() const {
  CoupledEvaluation e;
  e.qdd = e.F = e.limit_k = e.limit_b = VectorX::Zero(model_.nv);
  return e;
}

// The user's force at the state in data_ (body kinematics done): push, the
// tip against the shape its proxy rests on (eq. 3); pull, the spring-damper to
// the attachment point (eq. 4), and with an orientation its rotational half.
namespace {
// The tip's nearest surface and the proxy's face the same way within 60 degrees: the same side.
constexpr double kSameSide = 0.5;
}  // namespace

void CoupledDynamics::couplingForce(const Coupling& c, const VectorX& v, CouplingForce& out) {
  out = CouplingForce{};
  if (c.hand.mode == InteractionMode::Push) {
    if (!c.push_shape || c.contact_frame < 0) return;
    // Eq. (3), c = k_p d, with the tip's own depth and normal (the nearest surface to its centre)
    // while that is the side the proxy rests on; once the tip's centre has passed the middle of the
    // shape, the nearest surface is the far one, and d is the depth behind the proxy's surface
    // instead: it grows however deep the device goes and never flips. (Querying the tip keeps the
    // law smooth within a step; the proxy moves only between steps.)
    const SE3 oMf = framePose(model_, data_, c.contact_frame);
    const SE3 X = oMf * c.push_placement;
    TipContact touch = tipContact(*c.push_shape, X, c.hand.tip_position, c.hand.tip_radius);
    if (touch.depth > c.hand.tip_radius) {  // the tip's centre is inside
      const PointQuery at_proxy = pointQuery(*c.push_shape, X, c.proxy);
      if (at_proxy.valid && at_proxy.normal.dot(touch.normal) < kSameSide) {
        touch.depth = c.hand.tip_radius - (c.hand.tip_position - at_proxy.surface).dot(at_proxy.normal);
        touch.touching = touch.depth > 0.0;
        touch.normal = at_proxy.normal;
        touch.point = at_proxy.surface;
      }
    }
    if (!touch.touching) return;
    // The damper's rate: the tip's approach to the touched point of the link, along the normal.
    double depth_rate = 0.0;
    const Vector3 point_local = oMf.inverse().act(touch.point);
    if (c.gains.push_b > 0.0) {
      pointJacobian(model_, data_, c.contact_frame, point_local, J_);
      depth_rate = -(c.hand.tip_velocity - J_.topRows<3>() * v).dot(touch.normal);
    }
    const PushForce p = pushForce(touch, c.gains.push_k_p, scene_.push.max_force, c.gains.push_b, depth_rate);
    if (p.slack) return;
    out.coupled = true;
    out.frame = c.contact_frame;
    out.point_local = point_local;
    out.applied.point = p.point;
    out.applied.force = p.on_link;
    out.applied.clamped = p.clamped;
    if (!p.clamped) {
      out.K = c.gains.push_k_p * touch.normal * touch.normal.transpose();
      out.B = c.gains.push_b * touch.normal * touch.normal.transpose();
    }
  } else if (c.hand.mode == InteractionMode::Pull && c.pull_frame >= 0) {
    const Vector3 x = framePose(model_, data_, c.pull_frame).act(c.pull_point);
    pointJacobian(model_, data_, c.pull_frame, c.pull_point, J_);
    const Vector3 xd = J_.topRows<3>() * v;
    const PullForce p = pullForce(c.gains.pull_k, c.gains.pull_b, scene_.pull.max_stretch, scene_.pull.max_force, c.hand.tip_position,
                                  c.hand.tip_velocity, x, xd);
    out.coupled = true;
    out.frame = c.pull_frame;
    out.point_local = c.pull_point;
    out.applied.point = x;
    out.applied.force = p.on_robot;
    out.applied.clamped = p.clamped;
    if (!p.stretch_capped && !p.clamped) out.K = c.gains.pull_k * Matrix3::Identity();
    if (!p.clamped) out.B = c.gains.pull_b * Matrix3::Identity();
    if (c.hand.has_orientation && c.gains.pull_k_rot > 0.0) {
      const Matrix3 R = framePose(model_, data_, c.pull_frame).R * c.attach_rotation;
      const Vector3 w = J_.bottomRows<3>() * v;
      const PullTorque t = pullTorque(c.gains.pull_k_rot, c.gains.pull_b_rot, scene_.pull.max_angle, scene_.pull.max_torque,
                                      c.tip_rotation, c.hand.tip_angular_velocity, R, w);
      out.applied.torque = t.on_robot;
      out.applied.clamped = out.applied.clamped || t.clamped;
      if (!t.angle_capped && !t.clamped) out.k_rot = c.gains.pull_k_rot;
      if (!t.clamped) out.b_rot = c.gains.pull_b_rot;
    }
  }
  if (out.coupled && c.scale != 1.0) {
    const double f = rampShare(c.scale, c.carried_force, out.applied.force.norm());
    const double t = rampShare(c.scale, c.carried_torque, out.applied.torque.norm());
    out.applied.force *= f;
    out.K *= f;
    out.B *= f;
    out.applied.torque *= t;
    out.k_rot *= t;
    out.b_rot *= t;
  }
}

// A resume ramp's share of a coupling whose size is `now`: what it gave before the gap, `carried`,
// and `scale` of the way from there to `now` (scale alone when it gave nothing); all of a coupling
// that has not grown past what it gave. The coupling (force and linearisation) is scaled by it.
double CoupledDynamics::rampShare(double scale, double carried, double now) {
  if (carried <= 0.0) return scale;
  if (now <= carried) return 1.0;
  return (carried + scale * (now - carried)) / now;
}

void CoupledDynamics::placeGeometry(const VectorX& q, const GeometryModel& geometry, GeometryData& placed) {
  bodyKinematics(model_, data_, q);
  placed.place(geometry, model_, data_);
  placed_ = true;
}

void CoupledDynamics::evaluate(const CoupledInputs& in, const VectorX& q, const VectorX& v, CoupledEvaluation& out,
                               bool step_start) {
  // The couplings and the contacts need world poses; the dynamics then reuse them. At a step's start
  // the placement stage may have placed them already, at this q.
  const bool placed = in.ncouplings > 0 || (contacts_ && step_start);
  const bool reuse = step_start && placed_;
  if (step_start) placed_ = false;
  if (placed && !reuse) bodyKinematics(model_, data_, q);
  clearExternalForces(fext_);
  if (step_start && !free_bodies_.empty()) {  // a free body a hand acts on takes the integrators' step
    free_bodies_.clearDriven();
    for (int h = 0; h < in.ncouplings; ++h) {
      const int frame = in.couplings[h].actsOn();
      const int body = frame >= 0 ? model_.frame(frame).body : -1;
      const int k = body >= 0 ? free_bodies_.ofPart(model_.partOfBody(body)) : -1;
      if (k >= 0) free_bodies_.setDriven(k);
    }
  }
  bool any = false;
  out.ncouplings = in.ncouplings;
  for (int h = 0; h < in.ncouplings; ++h) {  // the hands' forces add up on their links
    CouplingForce& u = out.couplings[static_cast<size_t>(h)];
    couplingForce(in.couplings[h], v, u);
    if (!u.coupled) continue;
    addPointForce(model_, data_, PointForce{u.frame, u.point_local, u.applied.force, u.applied.torque}, fext_);
    any = true;
  }
  const std::vector<Force>* fext = any ? &fext_ : nullptr;
  const bool resolve = step_start && in.inverse_dynamics;
  if (resolve) {  // the controller's torque and the plant's bias, one pass
    if (placed) rneaAndBiasAtPlacements(model_, data_, v, in.qdd_cmd, fext);
    else rneaAndBias(model_, data_, q, v, in.qdd_cmd, fext);
    in.tau = data_.tau;
    if (scene_.joint_damping) in.tau += jointDamping(model_).cwiseProduct(v);
    for (const DofRange& r : floating_) in.tau.segment(r.begin, r.end - r.begin).setZero();
    if (in.uncommanded)
      for (const DofRange& r : *in.uncommanded) in.tau.segment(r.begin, r.end - r.begin).setZero();
  }
  tau_total_ = in.tau;
  if (scene_.joint_damping) addJointDamping(model_, v, tau_total_);
  if (in.pd.kp) {
    const VectorX &kp = *in.pd.kp, &kd = *in.pd.kd, &qr = *in.pd.q_ref, &vr = *in.pd.v_ref;
    for (int i = 0; i < model_.nb; ++i) {
      if (model_.joint_type[i] == JointType::Floating) continue;
      const int k = model_.v_index[i];
      if (kp[k] != 0.0 || kd[k] != 0.0) tau_total_[k] += kp[k] * (qr[k] - q[model_.q_index[i]]) + kd[k] * (vr[k] - v[k]);
    }
  }
  if (!limits_.empty()) limits_.apply(q, v, tau_total_, out.limit_k, out.limit_b);
  if (applied_acceleration_) {
    // H and the bias, no factors: the step reports what it applied.
    if (!resolve) biasAtPlacements(model_, data_, v, fext);
    crbaUpperAtPoses(model_, data_);
    out.F = tau_total_ - data_.bias;
    subtractHoldDamping(in, v, out.F, nullptr);
    return;
  }
  const bool solved = resolve  ? forwardDynamicsAtBias(model_, data_, tau_total_, placed)
                      : placed ? forwardDynamicsAtPoses(model_, data_, v, tau_total_, fext)
                               : forwardDynamics(model_, data_, q, v, tau_total_, fext);
  if (!solved) {
    out.qdd.setConstant(std::numeric_limits<double>::quiet_NaN());  // caught by the divergence guard
    return;
  }
  out.F = tau_total_ - data_.bias;  // = H qdd
  out.qdd = data_.qdd;
  subtractHoldDamping(in, v, out.F, &out.qdd);
}

void CoupledDynamics::subtractHoldDamping(const CoupledInputs& in, const VectorX& v, VectorX& F, VectorX* qdd) const {
  if (!in.hold) return;
  // -c H v on each held robot's block: H is block-diagonal across trees, so H^-1 of it is -c v there.
  for (const DofRange& r : *in.hold) {
    const int n = r.end - r.begin;
    data_.H.addSymmetricUpperTimes(r.begin, r.end, -r.rate, v, F);
    if (qdd) qdd->segment(r.begin, n) -= r.rate * v.segment(r.begin, n);
  }
}

void CoupledDynamics::linearSystem(const CoupledInputs& in, const CoupledEvaluation& at, const VectorX& v, double h,
                                   TreeMatrix& A, VectorX& rhs, std::vector<char>& factored) {
  // Every stored entry of H (ltdlFactor reads the upper triangle's ancestor entries; the others are
  // zero or, below the diagonal, never read).
  A.assign(data_.H);
  rhs = h * at.F;
  const int nv = model_.nv;
  if (scene_.joint_damping) {
    const auto damping = jointDamping(model_);  // a view: no copy
    for (int k = 0; k < nv; ++k) A.diagonal(k) += h * damping[k];
  }
  // The hold: A += h c H on each held range's upper triangle (its ancestor entries: H's others are zero).
  auto addHold = [&](int begin, int end, double hc) {
    for (int c = begin; c < end; ++c) {
      double* const a = A.column(c);
      const double* const H = data_.H.column(c);
      forEachAncestorRun(model_.dof_parent, model_.dof_run_start, c, [&](int r, int j) {
        for (int t = std::max(r, begin); t <= j; ++t) a[t] += hc * H[t];
      });
    }
  };
  if (in.hold)
    for (const DofRange& r : *in.hold) addHold(r.begin, r.end, h * r.rate);
  if (in.pd.kp) {
    // The PD's -kp dq - kd dv, implicitly: A += h kd + h^2 kp, rhs -= h^2 kp v.
    const VectorX &kp = *in.pd.kp, &kd = *in.pd.kd;
    for (int k = 0; k < nv; ++k) A.diagonal(k) += h * kd[k] + (h * h) * kp[k];
    rhs -= (h * h) * kp.cwiseProduct(v);
  }
  if (!limits_.empty()) {
    // The limits' -k d - b s, implicitly: A += h b + h^2 k, rhs -= h^2 k v (zero where none acts).
    for (int k = 0; k < nv; ++k) A.diagonal(k) += h * at.limit_b[k] + (h * h) * at.limit_k[k];
    rhs -= (h * h) * at.limit_k.cwiseProduct(v);
  }
  for (int h_i = 0; h_i < at.ncouplings; ++h_i) {  // each hand's stiffness and damping, summed
    const CouplingForce& u = at.couplings[static_cast<size_t>(h_i)];
    if (!u.coupled) continue;
    // Kept for appliedCouplings, once the step is done.
    Matrix6X& J = coupling_J_[static_cast<size_t>(h_i)];
    pointJacobian(model_, data_, u.frame, u.point_local, J);
    // A += J^T (h B + h^2 K) J, rhs -= h^2 J^T K J v over the 6 rows (translation: K, B at the
    // point; rotation: k_rot I, b_rot I), written out: no temporaries.
    KJ_.topRows<3>().noalias() = (h * u.B + h * h * u.K) * J.topRows<3>();
    KJ_.bottomRows<3>() = (h * u.b_rot + h * h * u.k_rot) * J.bottomRows<3>();
    Vector6 KJv;
    KJv.head<3>() = (h * h) * (u.K * (J.topRows<3>() * v));
    KJv.tail<3>() = (h * h * u.k_rot) * (J.bottomRows<3>() * v);
    // J's non-zero columns are the dofs that move the point (its body's and their ancestors', a
    // chain up dof_parent): on a humanoid's hand 14 of 38, and A's upper triangle only.
    const int body = model_.frame(u.frame).body;
    if (body < 0) continue;
    for (int c = model_.v_index[body] + model_.joint_nv[body] - 1; c >= 0; c = model_.dof_parent[c]) {
      rhs[c] -= J.col(c).dot(KJv);
      for (int r = c; r >= 0; r = model_.dof_parent[r]) A(r, c) += J.col(r).dot(KJ_.col(c));
    }
  }
  // A free body's block that is its inertia alone (upper triangles equal bit for bit: what ltdlFactor
  // reads) takes the factors formed once.
  constexpr int kFree = 6;
  for (const int b : free_blocks_) {
    double* const a = A.blockValues(b);
    const double* const inertia = free_inertia_.blockValues(b);
    bool alone = true;
    for (int c = 0; c < kFree && alone; ++c)
      alone = std::memcmp(a + c * kFree, inertia + c * kFree, sizeof(double) * static_cast<size_t>(c + 1)) == 0;
    if (!alone) continue;
    const double* const factors = free_factors_.blockValues(b);
    for (int c = 0; c < kFree; ++c) std::copy(factors + c * kFree, factors + c * kFree + c + 1, a + c * kFree);
    factored[static_cast<size_t>(b)] = 1;
  }
}

void CoupledDynamics::appliedCouplings(const CoupledEvaluation& at, const VectorX& v, const VectorX& v_end, double h,
                                       std::array<CouplingForce, kMaxHands>& applied) const {
  for (int i = 0; i < at.ncouplings; ++i) {
    const CouplingForce& u = at.couplings[static_cast<size_t>(i)];
    CouplingForce& a = applied[static_cast<size_t>(i)];
    a = u;
    if (!u.coupled) continue;
    const Matrix6X& J = coupling_J_[static_cast<size_t>(i)];
    // The point's displacement over the step (h J v+) and its velocity change (J (v+ - v)), and the same
    // for the link's rotation; the moving dofs are those of J's non-zero columns, a chain up dof_parent.
    Vector3 moved = Vector3::Zero(), dvel = Vector3::Zero(), turned = Vector3::Zero(), dspin = Vector3::Zero();
    const int body = model_.frame(u.frame).body;
    if (body < 0) continue;
    for (int c = model_.v_index[body] + model_.joint_nv[body] - 1; c >= 0; c = model_.dof_parent[c]) {
      moved += (h * v_end[c]) * J.col(c).head<3>();
      dvel += (v_end[c] - v[c]) * J.col(c).head<3>();
      turned += (h * v_end[c]) * J.col(c).tail<3>();
      dspin += (v_end[c] - v[c]) * J.col(c).tail<3>();
    }
    a.applied.force = u.applied.force - u.K * moved - u.B * dvel;
    a.applied.torque = u.applied.torque - u.k_rot * turned - u.b_rot * dspin;
  }
}

}  // namespace igms
