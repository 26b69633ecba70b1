// The client's side of push and pull (Son et al. 2003, section IV.2): what
// each servo cycle sends, the force on the user against an estimate of the
// robot, and the guards between that force and the hand. Shared by the
// networked client (igms-haptic) and the in-process scenario runner.
#pragma once

#include <memory>
#include <vector>

#include "haptic_client/servo/force_render.h"
#include "igms/haptic_input_t.hpp"
#include "core/interaction/proxy.h"
#include "core/scene/resolved_scene.h"
#include "core/simulation/simulation.h"

namespace igms {

// The stiffest spring between the hand and the scene, as the device feels it, N/m: the push's
// k_p or the pull's k (those enabled) times the workspace scale.
inline double couplingStiffness(const Scene& scene) {
  const double k = std::max(scene.push.enabled ? scene.push.k_p : 0.0, scene.pull.enabled ? scene.pull.k : 0.0);
  return k * scene.workspace_scale;
}

// The least damper that keeps the push's virtual coupling passive on a device sampled at rate_hz,
// N s/m: a spring held over a period T gives back up to k T / 2 per (m/s)^2 more than it took, which a
// damper b >= k T / 2 takes out (Colgate and Schenkel 1997). Scale-free: the device renders k and b
// times the same workspace scale and stiffness share.
inline double couplingMinDamping(const Scene& scene, double rate_hz) { return scene.push.k_p / (2.0 * rate_hz); }

class ClientInteraction {
 public:
  explicit ClientInteraction(const ResolvedScene& resolved);

  // Pull from this link point (frame -1: the scene's pull link and point).
  void setAttachment(int frame, const Vector3& point);
  // A 6-dof device's orientation this cycle (world <- tip) and angular velocity; call before fillInput.
  void setOrientation(bool has, const Eigen::Quaterniond& orientation, const Vector3& angular_velocity);
  // Step 2 of a cycle: the input (mode, tip, the link the last cycle found
  // touched, attachment) from the device. At the start of a 6-D pull the
  // grasped frame is fixed in the link so that the rotational spring starts relaxed.
  void fillInput(const Vector3& tip, const Vector3& tip_velocity, int buttons, haptic_input_t& msg);
  // Step 4: the force on the user (the reaction to c or F) against the
  // estimate `links` (every frame's world pose) at simulated time `estimate_time`. A push is the
  // spring between the tip and its proxy, which rests on the surface: on something that moves it is
  // eq. (3)'s reaction, on the ground or a solid obstacle a wall.
  // link_velocities: every frame's velocity in the estimate (frameVelocities), for the coupling's damper;
  // null: the touched point's from the last two estimates.
  Vector3 userForce(const std::vector<SE3>& links, double estimate_time, const Vector3& tip,
                    const Vector3& tip_velocity, const std::vector<Motion>* link_velocities = nullptr);
  // Guards: start-up guard, loss ramp, resync blend (after `resynced`), the
  // passivity controller (on the tip's velocity), clamp, and last the
  // per-cycle bound: whatever the path, the force reaching the hand changes
  // by at most max_step a cycle (counted when it acts).
  Vector3 render(const Vector3& on_user, const Vector3& tip_velocity, bool lost, bool resynced_after_gap,
                 double period, const RenderLimits& limits);
  // The 6-D pull's torque on the user from the last userForce (zero without an orientation).
  const Vector3& userTorque() const { return torque_on_user_; }
  // The torque's guards, as render's: loss ramp, passivity on the angular velocity, the device's
  // largest torque, the per-cycle bound. Call after render (it shares the loss ramp's scale).
  Vector3 renderTorque(const Vector3& on_user, double period, double max_torque, double max_step, bool passivity);

  bool pulling() const { return pulling_; }
  // The server is lost: a push in progress ends here, and a new one must start
  // at the surface. The tip sinks while the user feels nothing; that depth is
  // never delivered to the robot when the server returns.
  void disengagePush() { proxy_.release(); }
  // The tip's proxy (core/interaction/proxy.h) against the estimate: where the scene sees the hand.
  const Proxy& proxy() const { return proxy_; }
  // The geometry the proxy touches, and where it was placed for the last userForce (the estimate).
  const GeometryModel& geometry() const { return *geometry_; }
  const GeometryData& placedGeometry() const { return placed_; }
  // The last input fillInput made, as the server's step will take it (frames, not names).
  const InteractionInput& input() const { return input_; }
  double forceScale() const { return ramp_.scale(); }
  double maxForceStep() const { return max_force_step_; }
  int64_t slewLimited() const { return slew_limited_; }
  const PassivityController& passivity() const { return passivity_; }

 private:
  const Model& model_;
  const Scene& scene_;
  const int pull_frame_;  // -1: pull is off
  int attach_frame_;      // where the spring pulls: the scene's pull link, or the device's pick
  Vector3 attach_point_;
  StartupGuard guard_;
  LossRamp ramp_;
  ResyncBlend blend_;
  PassivityController passivity_, passivity_rot_;
  // The 6-D pull.
  bool has_orientation_ = false;
  Eigen::Quaterniond tip_q_ = Eigen::Quaterniond::Identity();
  Vector3 tip_w_ = Vector3::Zero();
  Matrix3 attach_rotation_ = Matrix3::Identity();  // link <- grasped frame
  Matrix3 last_link_R_ = Matrix3::Identity();      // the attachment link's estimated orientation
  Vector3 attach_w_ = Vector3::Zero();             // its angular velocity, differenced and low-passed
  Vector3 torque_on_user_ = Vector3::Zero(), last_torque_ = Vector3::Zero();
  bool pulling_ = false;
  std::shared_ptr<const GeometryModel> geometry_;  // the scene's (every link, free body, solid obstacle, the ground)
  GeometryData placed_;                            // at the estimate
  Proxy proxy_;
  bool touching_ = false;  // the proxy rests on something that moves: the input is a push
  int contact_frame_ = -1;
  Vector3 last_force_ = Vector3::Zero(), last_attach_ = Vector3::Zero(), attach_velocity_ = Vector3::Zero();
  double last_attach_time_ = -1.0;
  // The estimate the last call saw, and when: the touched surface's velocity for the coupling's damper.
  std::vector<SE3> last_links_;
  double last_links_time_ = -1.0;
  InteractionInput input_;
  double max_force_step_ = 0.0;
  int64_t slew_limited_ = 0;
};

}  // namespace igms
