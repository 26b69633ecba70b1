#include "tools/scenario/scenario_run.h"

#include "haptic_client/device/scripted_device.h"
#include "haptic_client/servo/client_interaction.h"
#include "server/collision/collision_world.h"
#include "core/geometry/point_query.h"
#include "core/model/environment_model.h"
#include "core/simulation/simulation.h"
#include "server/transport/input_gate.h"

#include <memory>

namespace igms {

ScenarioResult runScenario(const Scene& scene, const std::string& script, double seconds,
                           const std::string& save_edited, double reach_tolerance, bool device_limits) {
  ScenarioResult out;
  Simulation sim(resolveScene(scene));
  const Model& model = sim.model();
  // Every obstacle, and every one but the wall the motion is meant to reach.
  CollisionWorld all(model, sim.geometry()), not_wall(model, sim.geometry(), [](const std::string& o) { return o != "wall"; });
  ClientInteraction client(sim.resolved());
  std::vector<SE3> links = sim.linkPoses();
  std::unique_ptr<ScriptedDevice> device;  // none: no haptic input at all (the nominal run)
  if (!script.empty())
    device = std::make_unique<ScriptedDevice>(script, WorkspaceMap{scene.workspace_scale, scene.workspace_offset},
                                              [&](const std::string& name, SE3* X) {
                                                const int f = model.frameIndex(name);
                                                if (f < 0) return false;
                                                *X = links[static_cast<size_t>(f)];
                                                return true;
                                              },
                                              [&](const std::string& name) { return model.frameIndex(name); });
  // The end-effector: the first robot's line's frame, or its last link.
  const RobotSpec* robot = scene.robot();
  const std::string prefix = robot && !robot->name.empty() ? robot->name + "/" : "";
  const int last = model.parts.empty() ? -1 : model.parts.front().frame_end - 1;
  const int ee = robot && !robot->trajectory.frame.empty() ? model.frameIndex(prefix + robot->trajectory.frame) : last;
  out.q_columns = coordinateNames(model);
  for (const ModelPart& part : model.parts)
    if (part.free_body) out.bodies.push_back(part.name);
  const double period = scene.dt;
  haptic_input_t msg{};
  InteractionInput input;
  const FrameNames frames(model);
  const int steps = static_cast<int>(seconds / period + 0.5);
  int last_mode = 0;
  Vector3 last_rendered = Vector3::Zero();
  for (int k = 1; k <= steps; ++k) {
    const double t = (k - 1) * period;
    const DeviceReading r = device ? device->read(t) : DeviceReading{};
    const WorkspaceMap map{scene.workspace_scale, scene.workspace_offset};
    const Vector3 tip = map.toScene(r.position), tip_velocity = map.scale * r.velocity;
    client.setAttachment(r.attach_frame, r.attach_point);
    client.setOrientation(r.has_orientation, r.orientation, r.angular_velocity);
    client.fillInput(tip, tip_velocity, r.buttons, msg);
    msg.seq = k;
    RejectReason why;
    const bool ok = device && toInteractionInput(msg, frames, &input, &why);  // as the server would see it
    if (!sim.step(ok ? &input : nullptr)) {
      out.diverged = true;
      break;
    }
    links = sim.linkPoses();
    const Vector3 on_user =
        device ? client.userForce(links, sim.time(), tip, tip_velocity, &sim.linkVelocities()) : Vector3::Zero();
    RenderLimits limits;
    if (device && device_limits) {
      limits.max_force = device->limits().max_force;
      limits.max_step = device->limits().max_force_step;
    }
    const Vector3 rendered = client.render(on_user, tip_velocity, false, false, period, limits);
    if (device) device->write(rendered);
    ScenarioSample s;
    s.t = sim.time();
    s.q.assign(sim.q().data(), sim.q().data() + sim.q().size());
    s.mode = static_cast<int>(sim.outcome().mode);
    s.force_on_robot = sim.outcome().force_on_robot;
    s.rendered = rendered;
    s.ee = ee >= 0 ? links[static_cast<size_t>(ee)].p : Vector3::Zero();
    s.tip = device ? tip : Vector3::Zero();
    s.proxy = device ? client.proxy().position() : Vector3::Zero();
    const CollisionReport c = all.check(links), cn = not_wall.check(links);
    s.min_obstacle_distance = c.min_distance;
    s.in_collision = cn.in_collision;
    out.min_distance = std::min(out.min_distance, c.min_distance);
    if (c.in_collision) ++out.collision_steps_all;
    out.min_distance_excluding_goal = std::min(out.min_distance_excluding_goal, cn.min_distance);
    if (cn.in_collision) {
      ++out.collision_steps;
      if (out.first_collision < 0) {
        out.first_collision = s.t;
        out.first_collision_what = cn.closest_link + " hits " + cn.closest_obstacle;
      }
    }
    s.contacts = sim.contacts().n;
    s.max_penetration = sim.contacts().maxPenetration();
    const ContactSolveStats& solve = sim.contactStats();
    s.solver_sweeps = s.contacts > 0 ? solve.iterations : 0;
    s.solver_residual = s.contacts > 0 ? solve.residual : 0.0;
    if (s.contacts > 0) {
      ++out.solve.solves;
      out.solve.max_sweeps = std::max(out.solve.max_sweeps, s.solver_sweeps);
      out.solve.polish_rounds += solve.polish_rounds;
      out.solve.max_slip_angle = std::max(out.solve.max_slip_angle, solve.slip_angle);
      out.solve.max_linearised_angle = std::max(out.solve.max_linearised_angle, solve.linearised_angle);
      out.solve.max_residual = std::max(out.solve.max_residual, s.solver_residual);
    }
    out.solve.unconverged = solve.unconverged;
    out.solve.warm_dropped = solve.warm_dropped;
    out.solve.restitution_scaled = solve.restitution_scaled;
    out.solve.energy_capped = solve.energy_capped;
    out.solve.slips_unturned = solve.slips_unturned;
    out.solve.polish_cycles = solve.polish_cycles;
    out.solve.linearised_exact = solve.linearised_exact;
    out.solve.linearised = solve.linearised;
    out.solve.linearised_failed = solve.linearised_failed;
    out.solve.large_solves = solve.large_solves;
    out.solve.large_iterations = solve.large_iterations;
    out.solve.position_unconverged = solve.position_unconverged;
    if (const ContactDetection* d = sim.contactDetection()) {
      out.solve.near_rebuilds = d->nearRebuilds();
      out.solve.candidates_dropped = d->candidatePairsDropped();
    }
    out.max_contacts = std::max(out.max_contacts, s.contacts);
    out.max_penetration = std::max(out.max_penetration, s.max_penetration);
    if (out.reached_wall_time < 0 && robot && robot->trajectory.kind == TrajectorySpec::Kind::CartesianLine &&
        (s.ee - robot->trajectory.target).norm() <= reach_tolerance)
      out.reached_wall_time = s.t;
    out.max_user_force = std::max(out.max_user_force, rendered.norm());
    out.max_force_step = std::max(out.max_force_step, (rendered - last_rendered).norm());
    last_rendered = rendered;
    if (device && scene.push.enabled) {
      // How far the proxy is inside anything, against the state the hand felt, and the device behind it.
      const GeometryModel& geometry = client.geometry();
      const Proxy& proxy = client.proxy();
      double clear = 1e9;
      for (int g = 0; g < geometry.size(); ++g) {
        if (!geometry.object(g).touchable) continue;
        const PointQuery q = pointQuery(*geometry.object(g).shape, geometry.worldPose(g, links), proxy.position());
        if (q.valid) clear = std::min(clear, q.distance);
      }
      if (!proxy.free()) out.max_proxy_penetration = std::max(out.max_proxy_penetration, scene.push.tip_radius - clear);
      if (proxy.touches() > 0)
        out.max_device_behind_proxy = std::max(out.max_device_behind_proxy, (proxy.position() - tip).norm());
    }
    out.max_robot_force = std::max(out.max_robot_force, s.force_on_robot.norm());
    if (s.mode != last_mode) {
      if (s.mode) {
        out.interactions.push_back({s.t, s.t});
        out.interaction_modes.push_back(s.mode);
      }
      last_mode = s.mode;
    }
    if (s.mode && !out.interactions.empty()) out.interactions.back().second = s.t;
    out.final_ee = s.ee;
    out.samples.push_back(std::move(s));
  }
  if (!save_edited.empty()) sim.saveEdited(0, save_edited);  // the first robot's
  return out;
}

}  // namespace igms
