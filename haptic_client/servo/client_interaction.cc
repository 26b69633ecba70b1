#include "haptic_client/servo/client_interaction.h"

#include "core/geometry/deepest_contact.h"
#include "core/interaction/pull.h"
#include "core/interaction/push.h"

namespace igms {

ClientInteraction::ClientInteraction(const ResolvedScene& r)
    : model_(*r.model), scene_(r.scene), pull_frame_(r.pull_frame), attach_frame_(r.pull_frame),
      attach_point_(r.scene.pull.point) {}

void ClientInteraction::setAttachment(int frame, const Vector3& point) {
  if (pull_frame_ < 0) return;  // pull is off in this scene
  const int f = frame >= 0 && frame < static_cast<int>(model_.frames.size()) ? frame : pull_frame_;
  const Vector3 p = frame >= 0 ? point : scene_.pull.point;
  if (f == attach_frame_ && p == attach_point_) return;
  attach_frame_ = f;
  attach_point_ = p;
  last_attach_time_ = -1.0;  // a new point: its velocity starts afresh
  attach_velocity_.setZero();
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
  else if (scene_.push.enabled && contact_.touching && guard_.armed()) mode = haptic_input_t::MODE_PUSH;
  if (pulling_ != was_pulling) blend_.resync(20);  // engaging or releasing the spring: 20 ms, not a jolt
  if (was_pulling && !pulling_) clear_cycles_ = 0;  // a released tip is inert until it has left the robot
  if (mode != haptic_input_t::MODE_NONE && mode != static_cast<int8_t>(input_.mode)) passivity_.restart();  // a new interaction
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
  input_.mode = static_cast<InteractionMode>(mode);
  input_.tip_position = tip;
  input_.tip_velocity = tip_velocity;
  input_.tip_radius = scene_.push.tip_radius;
  input_.contact_frame = mode == haptic_input_t::MODE_PUSH ? contact_frame_ : -1;
  input_.attach_frame = mode == haptic_input_t::MODE_PULL ? attach_frame_ : -1;
  input_.attach_point = attach_point_;
}

Vector3 ClientInteraction::userForce(const std::vector<SE3>& links, double estimate_time, const Vector3& tip,
                                     const Vector3& tip_velocity) {
  Vector3 on_user = Vector3::Zero();
  contact_ = TipContact{};
  contact_frame_ = -1;
  if (pull_frame_ >= 0) {
    const Vector3 x = links[static_cast<size_t>(attach_frame_)].act(attach_point_);
    // The attachment's velocity from the estimate's own time base (a held
    // fallback cycle must not read as "stopped"), low-passed at 10 ms as
    // haptic loops do with differenced positions.
    if (estimate_time > last_attach_time_ + 1e-9) {
      const double dt = estimate_time - last_attach_time_;
      const double alpha = last_attach_time_ < 0 ? 0.0 : dt / (0.01 + dt);
      attach_velocity_ += alpha * ((x - last_attach_) / dt - attach_velocity_);
      last_attach_ = x;
      last_attach_time_ = estimate_time;
    }
    if (pulling_) {
      const PullForce f = pullForce(scene_.pull.k, scene_.pull.b, scene_.pull.max_stretch, scene_.pull.max_force, tip,
                                    tip_velocity, x, attach_velocity_);
      return -f.on_robot;
    }
  }
  if (!scene_.push.enabled) return on_user;
  const LinkContact touch = deepestContact(
      model_, [&](int f) { return links[static_cast<size_t>(f)]; }, tip, scene_.push.tip_radius);
  contact_ = touch.contact;
  contact_frame_ = touch.frame;
  // A push starts at the surface: contact engages only when it begins
  // shallow, and lasts until the tip leaves. A tip that appears deep inside
  // (a jump, or a pull released inside the wrist) pushes nothing.
  push_engaged_ = contact_.touching && (push_engaged_ || contact_.depth < kEngageDepth);
  // After a pull is let go the hand withdraws from where it held the robot, often through it (between a
  // gripper's fingers): the tip pushes nothing until it has been clear of every link for kReleaseClearCycles.
  if (clear_cycles_ < kReleaseClearCycles) {
    clear_cycles_ = touch.contact.touching ? 0 : clear_cycles_ + 1;
    push_engaged_ = false;
  }
  if (!push_engaged_) contact_ = TipContact{};
  if (contact_.touching) on_user = -pushForce(contact_, scene_.push.k_p, scene_.push.max_force).on_link;
  return on_user;
}

Vector3 ClientInteraction::render(const Vector3& on_user, const Vector3& tip_velocity, bool lost,
                                  bool resynced_after_gap, double period, const RenderLimits& limits) {
  if (resynced_after_gap) blend_.resync(10);  // back after a gap: 10 ms to the new force
  const double scale = ramp_.update(lost, period);
  Vector3 rendered = clampMagnitude(blend_.apply(guard_.apply(on_user) * scale, last_force_), limits.max_force);
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

}  // namespace igms
