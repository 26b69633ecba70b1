#include "core/scene/resolved_scene.h"

#include <set>

#include "core/model/configuration.h"
#include "core/model/environment_model.h"
#include "core/geometry/shape_inertia.h"
#include "core/model_io/mesh_fields.h"
#include "core/model_io/mesh_reader.h"
#include "core/model_io/model_loader.h"
#include "core/model_io/resource_path.h"

namespace igms {

namespace {

VectorX perJoint(const Scene& s, const std::string& at, const VectorX& given, double scalar, const char* key, int nv) {
  if (!given.size()) return VectorX::Constant(nv, scalar);
  if (given.size() != nv)
    throw SceneError(s.source + ": " + at + "controller." + key + " needs " + std::to_string(nv) + " entries");
  return given;
}

std::string list(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// A robot's model as its spec says: loaded (or parsed from a log's copy), its collision shapes set.
Model robotModel(const Scene& scene, const RobotSpec& spec, const std::string& at) {
  BuildOptions options;
  options.floating_base = spec.floating_base;
  options.gravity = scene.gravity;
  Model m = spec.model_text.empty() ? loadModel(spec.model_path, options)
                                    : parseModel(spec.model_text, spec.model_path, options);
  for (const LinkCollision& lc : spec.collision) {
    const int f = m.frameIndex(lc.link);
    if (f < 0) throw SceneError(scene.source + ": " + at + ".collision." + lc.link + ": no such link in " + spec.model_path);
    std::vector<CollisionShape>& shapes = m.frames[static_cast<size_t>(f)].collisions;
    if (!lc.keep_urdf) shapes.clear();
    shapes.insert(shapes.end(), lc.shapes.begin(), lc.shapes.end());
  }
  return m;
}

// A mesh a scene names (a free body's, an obstacle's) made touchable: its triangles, field and samples.
void attachSceneMesh(const Scene& scene, const std::string& at, CollisionShape& shape, TriangleMesh* triangles = nullptr) {
  if (shape.kind != CollisionShape::Kind::Mesh) return;
  RobotDescription d;
  d.source = scene.source;
  LinkDescription link;
  link.name = at;
  link.collisions.push_back(shape);
  d.links.push_back(link);
  attachDistanceFields(d, scene.source);
  shape = d.links[0].collisions[0];
  if (triangles) *triangles = *shape.triangles;
}

// A free body as a one-body model: a floating joint named after it, its shape to touch and to draw,
// its mass properties from the shape unless given.
Model freeBodyModel(const Scene& scene, const FreeBodySpec& spec, const std::string& at) {
  CollisionShape shape = spec.shape;
  TriangleMesh triangles;
  try {
    attachSceneMesh(scene, spec.name, shape, &triangles);
  } catch (const ModelError& e) {
    throw SceneError(scene.source + ": " + at + ".file: " + e.what());
  }
  MassProperties mp;
  try {
    mp = shapeMassProperties(shape, &triangles);
  } catch (const std::invalid_argument& e) {
    throw SceneError(scene.source + ": " + at + ": " + e.what());
  }
  const double mass = spec.mass > 0.0 ? spec.mass : spec.density * mp.volume;
  LinkDescription link;
  link.name = spec.name;
  link.mass = mass;
  link.com = mp.com;
  link.inertia = spec.has_inertia ? spec.inertia : Matrix3(mp.inertia * (mass / mp.volume));
  link.collisions.push_back(shape);
  VisualShape visual;
  visual.geometry = shape;
  visual.rgba = spec.rgba;
  visual.has_color = true;
  link.visuals.push_back(visual);
  RobotDescription d;
  d.name = spec.name;
  d.source = scene.source + ": " + at;
  d.links.push_back(link);
  BuildOptions options;
  options.floating_base = true;
  options.gravity = scene.gravity;
  Model m = buildModel(d, options);
  m.joint_name[0] = spec.name;
  return m;
}

// A floating root at pose M: [x y z qw qx qy qz].
void placeRoot(const SE3& M, VectorX& q, int at) {
  const Eigen::Quaterniond quat(M.R);
  q.segment<3>(at) = M.p;
  q[at + 3] = quat.w();
  q[at + 4] = quat.x();
  q[at + 5] = quat.y();
  q[at + 6] = quat.z();
}

}  // namespace

int ResolvedScene::materialIndex(const std::string& name) const {
  for (size_t k = 0; k < material_names.size(); ++k)
    if (material_names[k] == (name.empty() ? "default" : name)) return static_cast<int>(k);
  return 0;
}

namespace {

// The stages of resolveScene, in order.

// Each robot's model, then the environment holding them and the free bodies: one robot alone is an
// environment of one part (appended at the identity, its numbers are its own model's, bit for bit).
// robot_joints: each robot's joint names.
std::shared_ptr<const Model> sceneModel(const Scene& s, std::vector<std::vector<std::string>>& robot_joints) {
  std::vector<Model> robots;
  for (size_t k = 0; k < s.robots.size(); ++k) {
    const RobotSpec& spec = s.robots[k];
    const std::string at = spec.name.empty() ? "robot" : "robots[" + std::to_string(k) + "]";
    robots.push_back(robotModel(s, spec, at));
    robot_joints.push_back(robots.back().joint_name);
  }
  Model env = emptyEnvironment(s.name, s.source, s.gravity);
  for (size_t k = 0; k < robots.size(); ++k) {
    const RobotSpec& spec = s.robots[k];
    appendTree(env, robots[k], spec.name, spec.name.empty() ? "" : spec.name + "/",
               spec.floating_base ? SE3::Identity() : spec.base, false);
  }
  for (size_t k = 0; k < s.bodies.size(); ++k)
    appendTree(env, freeBodyModel(s, s.bodies[k], "bodies[" + std::to_string(k) + "]"), s.bodies[k].name, "",
               SE3::Identity(), true);
  // Names are how everything else finds a link: each one once.
  std::set<std::string> seen;
  for (const Frame& f : env.frames)
    if (!seen.insert(f.name).second)
      throw SceneError(s.source + ": two links are named '" + f.name +
                       "' (a free body named as a robot's link?): give one another name");
  return std::make_shared<const Model>(std::move(env));
}

// The mesh obstacles' meshes, loaded and attached to the scene's own copy.
void attachObstacleMeshes(ResolvedScene& r) {
  const Scene& s = r.scene;
  for (size_t k = 0; k < s.obstacles.size(); ++k) {
    const Obstacle& o = s.obstacles[k];
    if (o.shape.kind != CollisionShape::Kind::Mesh) continue;
    try {
      attachSceneMesh(s, o.name, r.scene.obstacles[k].shape);
    } catch (const ModelError& e) {
      throw SceneError(s.source + ": obstacles[] '" + o.name + "': " + e.what());
    }
  }
}

// What the scene does that a user may not expect: mimic joints taken as independent, links the tip
// passes through.
void warn(ResolvedScene& r) {
  const Scene& s = r.scene;
  const Model& m = *r.model;
  for (size_t i = 0; i < m.joint_mimic.size(); ++i)
    if (!m.joint_mimic[i].empty())
      r.warnings.push_back(s.robots[static_cast<size_t>(m.partOfBody(static_cast<int>(i)))].model_path + ": joint '" +
                           m.joint_name[i] + "' mimics '" + m.joint_mimic[i] +
                           "': treated as an independent coordinate");
  if (!s.push.enabled) return;
  // A link the tip passes through silently is the worst kind of no-op: say which.
  for (const Frame& f : m.frames) {
    if (f.body < 0 || m.body_name[static_cast<size_t>(f.body)] != f.name) continue;  // frames on a body: its own
    bool touchable = false;
    for (const CollisionShape& c : f.collisions) touchable |= c.kind != CollisionShape::Kind::Mesh || c.field;
    if (!touchable)
      r.warnings.push_back(s.source + ": push is on, but link '" + f.name +
                           "' has no collision geometry the tip can touch: it passes through");
  }
}

// Each robot's initial state, gains and material, checked against its part of the model; its
// trajectory's joints against its model's.
void resolveRobots(ResolvedScene& r, const std::vector<std::vector<std::string>>& robot_joints) {
  const Scene& s = r.scene;
  const Model& m = *r.model;
  for (size_t k = 0; k < s.robots.size(); ++k) {
    const RobotSpec& spec = s.robots[k];
    const ModelPart& part = m.parts[k];
    const std::string at = spec.name.empty() ? "" : "robots[" + std::to_string(k) + "].";
    const std::string initial = at + "initial";
    if (spec.q0.size() && spec.q0.size() != part.nq())
      throw SceneError(s.source + ": " + initial + ".q has " + std::to_string(spec.q0.size()) +
                       " entries, the model needs " + std::to_string(part.nq()));
    if (spec.v0.size() && spec.v0.size() != part.nv())
      throw SceneError(s.source + ": " + initial + ".v has " + std::to_string(spec.v0.size()) +
                       " entries, the model needs " + std::to_string(part.nv()));
    if (spec.q0.size()) r.q0.segment(part.q_begin, part.nq()) = spec.q0;
    else if (spec.floating_base) placeRoot(spec.base, r.q0, part.q_begin);
    if (spec.v0.size()) r.v0.segment(part.dof_begin, part.nv()) = spec.v0;
    ResolvedRobot robot;
    robot.name = spec.name;
    robot.part = static_cast<int>(k);
    robot.spec = static_cast<int>(k);
    robot.kp = perJoint(s, at, spec.kp, spec.kp_scalar, "kp", part.nv());
    robot.kd = perJoint(s, at, spec.kd, spec.kd_scalar, "kd", part.nv());
    r.kp.segment(part.dof_begin, part.nv()) = robot.kp;
    r.kd.segment(part.dof_begin, part.nv()) = robot.kd;
    r.robots.push_back(robot);
    r.part_material[k] = r.materialIndex(spec.material);
    if (spec.floating_base && spec.trajectory.kind != TrajectorySpec::Kind::None)
      throw SceneError(s.source + ": " + at + "trajectory: a floating-base robot has no joint-space trajectory to follow");
    const std::vector<std::string>& columns = spec.trajectory.joint_names;
    if (!columns.empty() && columns != robot_joints[k])
      throw SceneError(spec.trajectory.file + ": joints [" + list(columns) + "] are not the model's [" +
                       list(robot_joints[k]) + "] (" + spec.model_path + ")");
  }
}

// Each free body's pose, twist and material.
void resolveBodies(ResolvedScene& r) {
  const Scene& s = r.scene;
  const Model& m = *r.model;
  for (size_t k = 0; k < s.bodies.size(); ++k) {
    const FreeBodySpec& body = s.bodies[k];
    const ModelPart& part = m.parts[s.robots.size() + k];
    placeRoot(body.pose, r.q0, part.q_begin);
    // The floating joint's velocity is the body twist in its own frame.
    r.v0.segment<3>(part.dof_begin) = body.pose.R.transpose() * body.velocity;
    r.v0.segment<3>(part.dof_begin + 3) = body.pose.R.transpose() * body.angular_velocity;
    r.part_material[s.robots.size() + k] = r.materialIndex(body.material);
  }
}

// The pull's link (default: the first robot's last link) as a frame.
void resolvePull(ResolvedScene& r) {
  const Scene& s = r.scene;
  const Model& m = *r.model;
  if (!s.pull.enabled) return;
  std::string link = s.pull.link;
  if (link.empty()) {
    const ModelPart& first = m.parts.front();
    link = m.frames[static_cast<size_t>(first.frame_end - 1)].name;
  }
  r.pull_frame = m.frameIndex(link);
  if (r.pull_frame < 0) throw SceneError(s.source + ": interaction.pull.link: unknown link '" + link + "'");
}

}  // namespace

namespace {

// The shapes the scene holds itself: its obstacles (solid and ghost, in its order), then the ground.
std::vector<SceneShape> sceneShapes(const ResolvedScene& r) {
  const Scene& s = r.scene;
  std::vector<SceneShape> shapes;
  for (const Obstacle& o : s.obstacles) shapes.push_back(SceneShape{o.name, o.shape, r.materialIndex(o.material), o.solid});
  if (s.ground.enabled) {
    CollisionShape plane;
    plane.kind = CollisionShape::Kind::Plane;
    plane.placement = s.ground.pose;
    shapes.push_back(SceneShape{"ground", plane, r.materialIndex(s.ground.material), true});
  }
  return shapes;
}

}  // namespace

ResolvedScene resolveScene(const Scene& scene) {
  ResolvedScene r;
  r.scene = scene;
  const Scene& s = r.scene;
  r.material_names.push_back("default");
  for (const auto& [name, m] : s.materials)
    if (name != "default") r.material_names.push_back(name);
  std::vector<std::vector<std::string>> robot_joints;
  r.model = sceneModel(s, robot_joints);
  const Model& m = *r.model;
  attachObstacleMeshes(r);
  warn(r);
  // The initial state, the gains and the materials, part by part.
  r.q0 = neutralConfiguration(m);
  r.v0 = VectorX::Zero(m.nv);
  r.kp = VectorX::Zero(m.nv);
  r.kd = VectorX::Zero(m.nv);
  r.part_material.assign(m.parts.size(), 0);
  resolveRobots(r, robot_joints);
  resolveBodies(r);
  normalizeConfiguration(m, r.q0);
  resolvePull(r);
  r.geometry = std::make_shared<const GeometryModel>(m, r.part_material, sceneShapes(r));
  if (s.integrator == IntegratorKind::Rk4 && s.hasContact())
    throw SceneError(s.source + ": simulation.integrator: rk4 cannot take contact (an impulse per step): use "
                     "linearly_implicit or semi_implicit_euler");
  return r;
}


}  // namespace igms
