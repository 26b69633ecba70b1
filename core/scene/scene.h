// Scene: everything a simulation run needs, read from a YAML file. Immutable
// once loaded; gains live here, never in the Model. A scene is an environment
// (the paper's): robots, free bodies, the ground and obstacles, in contact.
//
//   name: puma_wall
//   robot: {model: ../models/puma560.urdf, floating_base: false}   # one robot, the short form
//   robot.collision:                           # optional, per link: instead of the URDF's shapes
//     link3: [{shape: cylinder, radius: 0.06, length: 0.4, xyz: [0, 0, 0.2]}]
//     link4: [from_urdf, {shape: sphere, radius: 0.05}]   # the URDF's and one more
//   gravity: [0, 0, -9.81]
//   initial: {q: [...], v: [...]}              # default: neutral, at rest
//   obstacles:                                 # boxes, spheres, cylinders, capsules, meshes
//     - {name: wall, shape: box, size: [0.05, 1.2, 1.2], xyz: [0.9, 0, 0.5], rpy: [0, 0, 0]}
//     - {name: table, shape: box, size: [1, 1, 0.05], xyz: [0.6, 0, 0.4], solid: true, material: wood}
//   trajectory:                                # none | joint_waypoints | cartesian_line | file
//     kind: cartesian_line
//     frame: ee_link
//     target: [0.8, 0.0, 0.3]
//     duration: 3.0
//   controller: {kp: 400, kd: 40, hold_damping: 2.0}   # scalars or one per joint; kind: computed_torque | pd
//   interaction:
//     push: {k_p: 2000, max_force: 40, tip_radius: 0.01, friction: 0.5}
//     coupling: {k: 2000, b: 20}               # the push's spring (k is k_p) and its damper, N s/m
//     pull: {k: 800, b: 10, max_force: 60, max_stretch: 0.08, link: ee_link, point: [0, 0, 0],
//            k_rot: 20, b_rot: 0.5, max_torque: 5, max_angle: 0.5}   # N m/rad, N m s/rad, N m, rad
//     workspace: {scale: 3.0, offset: [0.5, 0.0, 0.3]}   # scene = offset + scale * device
//   simulation: {integrator: linearly_implicit, dt: 0.001, rate_hz: 1000, joint_damping: true, joint_limits: true}
//
// The environment (docs/environment.md):
//   robots:                                    # several robots, instead of robot: (names prefixed "NAME/")
//     - {name: left, model: ..., floating_base: false, base: {xyz: [0, 0.5, 0]}, initial: {...},
//        trajectory: {...}, controller: {...}, collision: {...}, material: steel}
//   bodies:                                    # free bodies
//     - {name: box1, shape: box, size: [0.1, 0.1, 0.1], mass: 1.0, xyz: [...], rpy: [...], v: [...], w: [...],
//        material: wood}                       # or density: kg/m^3; inertia: [ixx, iyy, izz, ixy, ixz, iyz]
//   ground: {height: 0, rpy: [0, 0, 0], material: floor}    # or ground: true
//   materials: {wood: {friction: 0.5, restitution: 0.0}}
//   contact: {self_collision: false, margin: 0.005, iterations: 100, tolerance: 1e-10, bounce_velocity: 0.05}
//
// Paths are relative to the scene file. Errors name the file, line and key.
// Checks against the model (sizes, link names) are resolveScene's
// (resolved_scene.h).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/contact/contact_settings.h"
#include "core/integrate/integrator_kind.h"
#include "core/model/model.h"
#include "core/model/data.h"
#include "core/model/robot_description.h"

namespace igms {

class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};


struct Obstacle {
  std::string name;
  CollisionShape shape;  // placement = pose in the world
  bool solid = false;    // a fixed body that touches; else a ghost the server only monitors
  std::string material;  // "" : the default
};

// robot.collision: a link's collision shapes set by the scene (primitives, in the link's frame), instead of
// the URDF's or, with keep_urdf, beside them.
struct LinkCollision {
  std::string link;
  bool keep_urdf = false;
  std::vector<CollisionShape> shapes;
};

struct TrajectorySpec {
  enum class Kind { None, JointWaypoints, CartesianLine };
  Kind kind = Kind::None;
  std::vector<double> times;       // joint waypoints (also from a file)
  std::vector<VectorX> waypoints;
  std::string frame;               // cartesian line
  Vector3 target = Vector3::Zero();
  double duration = 0.0;
  std::vector<std::string> joint_names;  // a file's joints (the columns of q), checked against the model
  std::string file;                // kind: file, resolved; its content below (a log carries both)
  std::string file_text;
};

struct PushParams {
  bool enabled = false;
  double k_p = 2000.0;        // N/m (eq. 3)
  double max_force = 50.0;    // N, clamped and counted
  double tip_radius = 0.01;   // m
  // The tip's proxy (core/interaction/proxy.h) sticks on a surface while the device is inside this
  // friction cone (Coulomb), and slides at its edge beyond: without it a proxy slides round a thin
  // round link until it is under it.
  double friction = 0.5;
  // The virtual coupling's damper (interaction.coupling.b, N s/m) on the rate the tip goes in:
  // c = k_p d + b d'. Passive on a device at period T when b >= k_p T / 2 (Colgate and Schenkel
  // 1997), checked at load; by default b = kCouplingTime k_p.
  double b = 0.0;
};

// The default coupling damper per unit stiffness, s: damps a 1 kg body on the push spring to a
// steady slide within 0.2 s (docs/client.md, "The virtual coupling").
constexpr double kCouplingTime = 0.01;

struct PullParams {
  bool enabled = false;
  double k = 500.0;            // N/m (eq. 4)
  double b = 10.0;             // N s/m
  double max_force = 80.0;     // N
  double max_stretch = 0.1;    // m: the spring's stretch is capped, so a jump cannot inject a huge force
  std::string link;            // attachment link (default: the last link of the model)
  Vector3 point = Vector3::Zero();
  // The rotational half of the 6-D pull, for devices that report an orientation
  // (k_rot 0: the pull stays 3-D whatever the device).
  double k_rot = 0.0;          // N m/rad
  double b_rot = 0.0;          // N m s/rad
  double max_torque = 5.0;     // N m
  double max_angle = 0.5;      // rad: the rotational spring's stretch cap
};

// How a robot's joints are driven.
enum class ControllerKind {
  ComputedTorque,  // inverse dynamics along the trajectory, PD on the error (the paper's); passive without one
  Pd,              // joint PD toward the trajectory or, without one, the initial posture (a legged robot standing)
};

struct RobotSpec {
  std::string name;            // "" : the short form robot: (its names unprefixed)
  std::string model_path;      // resolved
  std::string model_text;      // non-empty: the model file's content (a log's copy), parsed instead of reading model_path
  bool floating_base = false;
  SE3 base;                    // where the root sits in the world (a floating root: its initial pose)
  VectorX q0, v0;              // empty: neutral (at the base), at rest
  std::vector<LinkCollision> collision;  // its collision: key, applied by resolveScene
  TrajectorySpec trajectory;
  ControllerKind controller = ControllerKind::ComputedTorque;
  VectorX kp, kd;              // gains per dof as written (empty: the scalars)
  double kp_scalar = 100.0, kd_scalar = 20.0;
  double hold_damping = 2.0;   // 1/s: while the user interacts, velocities decay at this rate (-c H v)
  std::string material;        // its links' ("" : the default)
};

// A free body: one rigid body on a floating joint, moved by gravity and contact.
struct FreeBodySpec {
  std::string name;
  CollisionShape shape;        // placement unused; a mesh's file and scale
  double mass = -1.0;          // kg (< 0: from density x volume)
  double density = 1000.0;     // kg/m^3
  bool has_inertia = false;    // inertia given (about the centre of mass, body axes); else from the shape
  Matrix3 inertia = Matrix3::Zero();
  SE3 pose;                    // initial, world
  Vector3 velocity = Vector3::Zero();          // initial, world: of the body frame's origin
  Vector3 angular_velocity = Vector3::Zero();  // initial, world
  std::string material;
  Eigen::Vector4d rgba = Eigen::Vector4d(0.8, 0.5, 0.2, 1.0);
};

struct GroundSpec {
  bool enabled = false;
  SE3 pose;                    // the plane is this frame's z = 0, solid below (height: pose.p.z())
  std::string material;
};

struct Scene {
  std::string name;
  std::string source;          // the scene file
  std::string text;            // its content (logged so a replay can rebuild the run)
  Vector3 gravity = Vector3(0.0, 0.0, -9.81);
  std::vector<RobotSpec> robots;      // robot: (one) or robots:; none for a scene of free bodies
  std::vector<FreeBodySpec> bodies;
  GroundSpec ground;
  std::vector<Obstacle> obstacles;
  std::map<std::string, Material> materials;  // by name, "default" included
  ContactSettings contact;
  PushParams push;
  PullParams pull;
  double workspace_scale = 1.0;
  Vector3 workspace_offset = Vector3::Zero();
  IntegratorKind integrator = IntegratorKind::LinearlyImplicit;
  double dt = 1e-3;            // s
  double rate_hz = 1000.0;
  bool joint_damping = true;
  // URDF position limits enforced (core/simulation/joint_limits.h): a stiff, damped one-sided spring.
  bool joint_limits = true;

  // The ghost obstacles the server monitors (FCL); solid ones take part in contact instead.
  bool needsCollision() const {
    for (const Obstacle& o : obstacles)
      if (!o.solid) return true;
    return false;
  }
  // Anything here that touches: the ground, free bodies, several robots, a solid obstacle, or a robot's
  // own links (contact.self_collision).
  bool hasContact() const {
    bool solid = false;
    for (const Obstacle& o : obstacles) solid |= o.solid;
    return ground.enabled || !bodies.empty() || robots.size() > 1 || solid || contact.self_collision;
  }
  // The robot the one-robot tools speak of: the first (none: null).
  const RobotSpec* robot() const { return robots.empty() ? nullptr : &robots.front(); }
};

Scene loadScene(const std::string& path);
// `files` (resolved path -> content) stands in for the disk where a scene reads another
// file (trajectory.file): a log carries the content, the path may not exist here.
Scene parseScene(const std::string& yaml, const std::string& source, const std::string& base_dir,
                 const std::map<std::string, std::string>* files = nullptr);

}  // namespace igms
