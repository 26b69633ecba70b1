#include "tests/support/kdl_from_urdf.h"

#include <stdexcept>
#include <urdf_parser/urdf_parser.h>

namespace igms::test {
namespace {

KDL::Frame toKdl(const urdf::Pose& p) {
  return KDL::Frame(KDL::Rotation::Quaternion(p.rotation.x, p.rotation.y, p.rotation.z, p.rotation.w),
                    KDL::Vector(p.position.x, p.position.y, p.position.z));
}

KDL::RigidBodyInertia toKdl(const urdf::InertialSharedPtr& in) {
  if (!in) return KDL::RigidBodyInertia();
  const KDL::RigidBodyInertia about_com(
      in->mass, KDL::Vector::Zero(), KDL::RotationalInertia(in->ixx, in->iyy, in->izz, in->ixy, in->ixz, in->iyz));
  return toKdl(in->origin) * about_com;
}

KDL::Joint toKdl(const urdf::Joint& j) {
  const KDL::Frame F = toKdl(j.parent_to_joint_origin_transform);
  const KDL::Vector axis = F.M * KDL::Vector(j.axis.x, j.axis.y, j.axis.z);
  switch (j.type) {
    case urdf::Joint::REVOLUTE:
    case urdf::Joint::CONTINUOUS: return KDL::Joint(j.name, F.p, axis, KDL::Joint::RotAxis);
    case urdf::Joint::PRISMATIC: return KDL::Joint(j.name, F.p, axis, KDL::Joint::TransAxis);
    default: return KDL::Joint(j.name, KDL::Joint::Fixed);
  }
}

void addChildren(const urdf::LinkConstSharedPtr& link, KdlRobot& out) {
  if (link->child_links.empty()) out.leaves.push_back(link->name);
  for (const auto& child : link->child_links) {
    const urdf::Joint& j = *child->parent_joint;
    KDL::Segment seg(child->name, toKdl(j), toKdl(j.parent_to_joint_origin_transform), toKdl(child->inertial));
    if (!out.tree.addSegment(seg, link->name)) throw std::runtime_error("KDL refused segment " + child->name);
    addChildren(child, out);
  }
}

}  // namespace

KdlRobot kdlFromUrdf(const std::string& xml) {
  const urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDF(xml);
  if (!urdf) throw std::runtime_error("urdfdom rejected the URDF");
  KdlRobot out;
  out.tree = KDL::Tree(urdf->getRoot()->name);
  addChildren(urdf->getRoot(), out);
  for (const auto& [name, element] : out.tree.getSegments()) {
    const KDL::Segment& seg = GetTreeElementSegment(element);
    if (seg.getJoint().getType() != KDL::Joint::Fixed)
      out.q_nr_of_joint[seg.getJoint().getName()] = GetTreeElementQNr(element);
  }
  return out;
}

}  // namespace igms::test
