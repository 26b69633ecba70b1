#include "haptic_client/servo/client_interaction.h"

#include <algorithm>

#include "core/interaction/pull.h"
#include "core/interaction/push.h"

namespace igms {

ClientInteraction::ClientInteraction(const ResolvedScene& r)
    : model_(*r.model), scene_(r.scene), pull_frame_(r.pull_frame), attach_frame_(r.pull_frame),
      attach_point_(r.scene.pull.point), geometry_(r.geometry), placed_(*geometry_),
      proxy_(*geometry_, r.scene.push.friction),
      last_links_(r.model->frames.size()) {}

void ClientInteraction::setAttachment(int frame, const Vector3& point) {
  if (pull_frame_ < 0) return;  // pull is off in this scene
  const int f = frame >= 0 && frame < static_cast<int>(model_.frames.size()) ? frame : pull_frame_;
  const Vector3 p = frame >= 0 ? point : scene_.pull.point;
  if (f == attach_frame_ && p == attach_point_) return;
  attach_frame_ = f;
  attach_point_ = p;
  last_attach_time_ = -1.0;  // a new point: its velocity starts afresh
  attach_velocity_.setZero();
  attach_w_.setZero();
}

void ClientInteraction::setOrientation(bool has, const Eigen::Quaterniond& orientation,
                                       const Vector3& angular_velocity) {
  has_orientation_ = has && scene_.pull.k_rot > 0.0;  // a 3-D pull scene ignores the orientation
  tip_q_ = orientation.normalized();
  tip_w_ = angular_velocity;
}

void ClientInteraction::fillInput(const Vector3& tip, const Vector3& tip_velocity, int buttons,
                                  haptic_input_t& msg) {
  // Pull while the button is held; push when the tip touches a link. Like the
  // force, a push waits for the start-up guard: a tip that starts inside a
  // link must leave it once before it can push.
  int8_t mode = haptic_input_t::MODE_NONE;
  const bool was_pulling = pulling_;
  pulling_ = (buttons & 1) && pull_frame_ >= 0;
  if (pulling_) mode = haptic_input_t::MODE_PULL;
  else if (scene_.push.enabled && touching_ && guard_.armed()) mode = haptic_input_t::MODE_PUSH;
  if (pulling_ != was_pulling) blend_.resync(20);  // engaging or releasing the spring: 20 ms, not a jolt
  // The grab: the grasped frame is the tip's orientation in the link now (relaxed rotational spring).
  if (pulling_ && !was_pulling) attach_rotation_ = last_link_R_.transpose() * tip_q_.toRotationMatrix();
  if (mode != haptic_input_t::MODE_NONE && mode != static_cast<int8_t>(input_.mode)) {  // a new interaction
    passivity_.restart();
    passivity_rot_.restart();
  }
  msg.mode = mode;
  for (int i = 0; i < 3; ++i) {
    msg.tip_position[i] = tip[i];
    msg.tip_velocity[i] = tip_velocity[i];
  }
  msg.tip_radius = scene_.push.tip_radius;
  msg.buttons = buttons;
  msg.contact_link = mode == haptic_input_t::MODE_PUSH ? model_.frames[static_cast<size_t>(contact_frame_)].name : "";
  msg.attach_link = mode == haptic_input_t::MODE_PULL ? model_.frames[static_cast<size_t>(attach_frame_)].name : "";
  for (int i = 0; i < 3; ++i) msg.attach_point[i] = attach_point_[i];
  msg.has_orientation = has_orientation_;
  const Eigen::Quaterniond attach_q(attach_rotation_);
  const double tq[4] = {tip_q_.w(), tip_q_.x(), tip_q_.y(), tip_q_.z()};
  const double aq[4] = {attach_q.w(), attach_q.x(), attach_q.y(), attach_q.z()};
  for (int i = 0; i < 4; ++i) {
    msg.tip_orientation[i] = has_orientation_ ? tq[i] : (i == 0 ? 1.0 : 0.0);
    msg.attach_orientation[i] = has_orientation_ ? aq[i] : (i == 0 ? 1.0 : 0.0);
  }
  for (int i = 0; i < 3; ++i) msg.tip_angular_velocity[i] = has_orientation_ ? tip_w_[i] : 0.0;
  input_.has_orientation = has_orientation_;
  input_.tip_orientation = tip_q_;
  input_.tip_angular_velocity = tip_w_;
  input_.attach_orientation = attach_q;
  input_.mode = static_cast<InteractionMode>(mode);
  input_.tip_position = tip;
  input_.tip_velocity = tip_velocity;
  input_.tip_radius = scene_.push.tip_radius;
  input_.attach_frame = mode == haptic_input_t::MODE_PULL ? attach_frame_ : -1;
  input_.attach_point = attach_point_;
}

Vector3 ClientInteraction::userForce(const std::vector<SE3>& links, double estimate_time, const Vector3& tip,
                                     const Vector3& tip_velocity, const std::vector<Motion>* link_velocities) {
  Vector3 on_user = Vector3::Zero();
  touching_ = false;
  contact_frame_ = -1;
  torque_on_user_.setZero();
  if (pull_frame_ >= 0) {
    const SE3& link = links[static_cast<size_t>(attach_frame_)];
    const Vector3 x = link.act(attach_point_);
    // The attachment's velocity from the estimate's own time base (a held
    // fallback cycle must not read as "stopped"), low-passed at 10 ms as
    // haptic loops do with differenced positions.
    if (estimate_time > last_attach_time_ + 1e-9) {
      const double dt = estimate_time - last_attach_time_;
      const double alpha = last_attach_time_ < 0 ? 0.0 : dt / (0.01 + dt);
      attach_velocity_ += alpha * ((x - last_attach_) / dt - attach_velocity_);
      if (alpha > 0.0) attach_w_ += alpha * (rotationLog(link.R * last_link_R_.transpose()) / dt - attach_w_);
      last_attach_ = x;
      last_attach_time_ = estimate_time;
    }
    last_link_R_ = link.R;
    if (pulling_ && has_orientation_)  // the 6-D pull's rotational half, against the estimate as the server's
      torque_on_user_ = -pullTorque(scene_.pull.k_rot, scene_.pull.b_rot, scene_.pull.max_angle,
                                    scene_.pull.max_torque, tip_q_.toRotationMatrix(), tip_w_,
                                    link.R * attach_rotation_, attach_w_)
                             .on_robot;
    if (pulling_) {
      const PullForce f = pullForce(scene_.pull.k, scene_.pull.b, scene_.pull.max_stretch, scene_.pull.max_force, tip,
                                    tip_velocity, x, attach_velocity_);
      return -f.on_robot;
    }
  }
  if (!scene_.push.enabled) return on_user;
  // The proxy follows the tip, free while a pull holds and after one until the tip has come out of
  // what it held (a released hand withdraws through the gripper), as the server's does.
  placed_.place(*geometry_, links);
  proxy_.update(*geometry_, placed_, tip, scene_.push.tip_radius, pulling_);
  // The spring to the proxy, at the push's stiffness and limit. On something that moves it is eq. (3)'s
  // reaction, along that surface's normal as the server applies c (the proxy's friction is the hand's
  // alone, so it is left out there: what the body gets, the hand feels); on what does not, the whole
  // spring, a wall with friction.
  // The coupling's damper acts along the touched surface's normal on the rate the tip goes in, against
  // that surface point's velocity in the estimate, as the server's does against the robot's.
  const Vector3 stretch = proxy_.stretch(tip);
  const double dt = estimate_time - last_links_time_;
  const bool moved = last_links_time_ >= 0.0 && dt > 1e-9;
  const int k = proxy_.deepest(*geometry_, tip, true);
  if (k >= 0) {
    touching_ = true;
    contact_frame_ = geometry_->object(proxy_.touch(k).geom).frame;
    const ProxyTouch& touch = proxy_.touch(k);
    const Vector3& n = touch.normal;
    Vector3 surface_velocity = Vector3::Zero();
    const size_t f = static_cast<size_t>(contact_frame_);
    if (link_velocities) {
      const Motion& m = (*link_velocities)[f];
      surface_velocity = m.v + m.w.cross(touch.surface - links[f].p);
    } else if (moved) {  // the same material point at the last estimate and this one
      surface_velocity = (touch.surface - last_links_[f].act(links[f].inverse().act(touch.surface))) / dt;
    }
    const double depth_rate = -(tip_velocity - surface_velocity).dot(n);
    on_user = std::max(0.0, scene_.push.k_p * stretch.dot(n) + scene_.push.b * depth_rate) * n;
    // The server pushes from the step whose input says so, the next one: this cycle's step did not, so
    // the hand feels nothing yet either (what the body gets, the hand feels). Before the start-up guard
    // arms the force stands, for the guard to see a tip that starts inside.
    if (input_.mode != InteractionMode::Push && guard_.armed()) on_user.setZero();
  } else {
    on_user = scene_.push.k_p * stretch;
    const int w = proxy_.deepest(*geometry_, tip, false);
    if (w >= 0) {  // a wall: its damper along the normal, never pulling the hand in
      const Vector3& n = proxy_.touch(w).normal;
      const double normal = on_user.dot(n);
      on_user += (std::max(0.0, normal - scene_.push.b * tip_velocity.dot(n)) - normal) * n;
    }
  }
  if (!link_velocities && (moved || last_links_time_ < 0.0)) {  // the differences' last estimate
    std::copy(links.begin(), links.end(), last_links_.begin());
    last_links_time_ = estimate_time;
  }
  return clampMagnitude(on_user, scene_.push.max_force);
}

Vector3 ClientInteraction::render(const Vector3& on_user, const Vector3& tip_velocity, bool lost,
                                  bool resynced_after_gap, double period, const RenderLimits& limits) {
  if (resynced_after_gap) blend_.resync(10);  // back after a gap: 10 ms to the new force
  const double scale = ramp_.update(lost, period);
  Vector3 rendered = clampMagnitude(blend_.apply(guard_.apply(on_user * limits.stiffness_scale) * scale, last_force_),
                                    limits.max_force);
  if (limits.passivity) {  // on the force the device can render, so the balance is what the hand gets
    passivity_.setTolerance(limits.passivity_tolerance);
    rendered = clampMagnitude(passivity_.apply(rendered, tip_velocity, period), limits.max_force);
  }
  const Vector3 step = rendered - last_force_;
  if (step.norm() > limits.max_step) {
    rendered = last_force_ + clampMagnitude(step, limits.max_step);
    ++slew_limited_;
  }
  passivity_.commit(rendered, tip_velocity, period);
  max_force_step_ = std::max(max_force_step_, (rendered - last_force_).norm());
  last_force_ = rendered;
  return rendered;
}

Vector3 ClientInteraction::renderTorque(const Vector3& on_user, double period, double max_torque, double max_step,
                                        bool passivity) {
  if (!(max_torque > 0.0)) return Vector3::Zero();  // a 3-dof device
  // The loss ramp's scale, as render set it this cycle.
  Vector3 rendered = clampMagnitude(guard_.armed() ? Vector3(on_user * ramp_.scale()) : Vector3::Zero(), max_torque);
  if (passivity) rendered = clampMagnitude(passivity_rot_.apply(rendered, tip_w_, period), max_torque);
  const Vector3 step = rendered - last_torque_;
  if (step.norm() > max_step) {
    rendered = last_torque_ + clampMagnitude(step, max_step);
    ++slew_limited_;
  }
  passivity_rot_.commit(rendered, tip_w_, period);
  last_torque_ = rendered;
  return rendered;
}

}  // namespace igms
