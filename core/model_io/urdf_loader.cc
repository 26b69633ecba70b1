#include "core/model_io/urdf_loader.h"

#include "core/model_io/mesh_fields.h"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <mutex>
#include <sstream>

namespace igms {
namespace {

// urdfdom reports through console_bridge; keep its words for our error.
class CollectingHandler : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors.push_back(text);
  }
  std::vector<std::string> errors;
};

SE3 toSE3(const urdf::Pose& pose) {
  const auto& r = pose.rotation;
  Eigen::Quaterniond quat(r.w, r.x, r.y, r.z);
  SE3 X;
  X.R = quat.norm() > 0.0 ? quat.normalized().toRotationMatrix() : Matrix3::Identity();
  X.p = Vector3(pose.position.x, pose.position.y, pose.position.z);
  return X;
}

Vector3 toVector(const urdf::Vector3& v) { return {v.x, v.y, v.z}; }

CollisionShape toShape(const urdf::Geometry& geometry, const urdf::Pose& origin) {
  CollisionShape s;
  s.placement = toSE3(origin);
  switch (geometry.type) {
    case urdf::Geometry::BOX:
      s.kind = CollisionShape::Kind::Box;
      s.size = toVector(static_cast<const urdf::Box&>(geometry).dim);
      break;
    case urdf::Geometry::CYLINDER: {
      const auto& g = static_cast<const urdf::Cylinder&>(geometry);
      s.kind = CollisionShape::Kind::Cylinder;
      s.size = Vector3(g.radius, g.length, 0.0);
      break;
    }
    case urdf::Geometry::SPHERE:
      s.kind = CollisionShape::Kind::Sphere;
      s.size = Vector3(static_cast<const urdf::Sphere&>(geometry).radius, 0.0, 0.0);
      break;
    case urdf::Geometry::MESH: {
      const auto& g = static_cast<const urdf::Mesh&>(geometry);
      s.kind = CollisionShape::Kind::Mesh;
      s.mesh_file = g.filename;
      s.mesh_scale = toVector(g.scale);
      break;
    }
  }
  return s;
}

LinkDescription toLink(const urdf::Link& link) {
  LinkDescription l;
  l.name = link.name;
  if (link.inertial) {
    const urdf::Inertial& in = *link.inertial;
    const SE3 X = toSE3(in.origin);
    Matrix3 I;
    I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    l.mass = in.mass;
    l.com = X.p;
    l.inertia = X.R * I * X.R.transpose();  // the inertial rpy rotates the tensor
  }
  for (const auto& c : link.collision_array) {
    if (c && c->geometry) l.collisions.push_back(toShape(*c->geometry, c->origin));
  }
  for (const auto& v : link.visual_array) {
    if (!v || !v->geometry) continue;
    VisualShape shape;
    shape.geometry = toShape(*v->geometry, v->origin);
    if (v->material) {
      const urdf::Color& c = v->material->color;
      // urdfdom leaves a material without <color> black and transparent.
      shape.has_color = c.r != 0.0f || c.g != 0.0f || c.b != 0.0f || c.a != 0.0f;
      if (shape.has_color) shape.rgba = Eigen::Vector4d(c.r, c.g, c.b, c.a);
    }
    l.visuals.push_back(shape);
  }
  return l;
}

JointDescription toJoint(const urdf::Joint& joint, const std::string& source) {
  JointDescription j;
  j.name = joint.name;
  j.parent = joint.parent_link_name;
  j.child = joint.child_link_name;
  j.origin = toSE3(joint.parent_to_joint_origin_transform);
  j.axis = toVector(joint.axis);
  using T = JointDescription::Type;
  switch (joint.type) {
    case urdf::Joint::REVOLUTE: j.type = T::Revolute; break;
    case urdf::Joint::CONTINUOUS: j.type = T::Continuous; break;
    case urdf::Joint::PRISMATIC: j.type = T::Prismatic; break;
    case urdf::Joint::FIXED: j.type = T::Fixed; break;
    case urdf::Joint::FLOATING: j.type = T::Floating; break;
    case urdf::Joint::PLANAR: j.type = T::Planar; break;
    default: throw ModelError(source + ": joint '" + joint.name + "': unknown joint type");
  }
  if (joint.mimic) {
    j.mimic = joint.mimic->joint_name;
    j.mimic_multiplier = joint.mimic->multiplier;
    j.mimic_offset = joint.mimic->offset;
  }
  if (joint.dynamics) {
    j.damping = joint.dynamics->damping;
    j.friction = joint.dynamics->friction;
  }
  if (joint.limits && j.type != T::Continuous) {
    j.lower = joint.limits->lower;
    j.upper = joint.limits->upper;
  }
  if (joint.limits) {
    if (joint.limits->effort > 0.0) j.effort = joint.limits->effort;
    if (joint.limits->velocity > 0.0) j.velocity = joint.limits->velocity;
  }
  return j;
}

}  // namespace

RobotDescription parseUrdfDescription(const std::string& xml, const std::string& source) {
  // console_bridge's handler is process-wide.
  static std::mutex mutex;
  std::lock_guard<std::mutex> lock(mutex);
  CollectingHandler handler;
  console_bridge::useOutputHandler(&handler);
  urdf::ModelInterfaceSharedPtr urdf;
  try {
    urdf = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    handler.errors.push_back(e.what());
  }
  console_bridge::restorePreviousOutputHandler();
  // urdfdom logs some errors and still returns a model with the element
  // half-read (an <inertial> with an unreadable number keeps mass, loses
  // inertia): any error it reports fails the load, so nothing is lost silently.
  if (!urdf || !handler.errors.empty()) {
    std::string why;
    for (const auto& e : handler.errors) why += (why.empty() ? "" : "; ") + e;
    throw ModelError(source + ": " + (why.empty() ? "not a valid URDF" : why));
  }
  RobotDescription d;
  d.name = urdf->getName();
  d.source = source;
  for (const auto& [name, link] : urdf->links_) d.links.push_back(toLink(*link));
  for (const auto& [name, joint] : urdf->joints_) d.joints.push_back(toJoint(*joint, source));
  return d;
}

RobotDescription loadUrdfDescription(const std::string& path) {
  RobotDescription d = parseUrdfDescription(readModelFile(path), path);
  attachDistanceFields(d, path);
  return d;
}

Model loadUrdfModel(const std::string& path, const BuildOptions& options, std::vector<std::string>* warnings) {
  return buildModel(loadUrdfDescription(path), options, warnings);
}

}  // namespace igms
