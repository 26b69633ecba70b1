// Model: the immutable description of an articulated body (a tree of rigid
// bodies connected by one-coordinate joints, optionally on a floating base).
//
// Bodies are numbered 0..nb-1 in topological order (parent[i] < i); parent -1 is
// the fixed world (or, for a fixed base, the URDF root link, which coincides with
// the world). Links joined by fixed joints are merged into one body; every URDF
// link survives as a Frame placed on its body.
//
// Paper symbols (Son et al. 2003, after Craig): X_tree[i] and the joint motion
// give iR_p and iP_i; inertia[i] holds m_i, m_i iP_Ci and the inertia; axis[i] is
// iZ_i.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/model/distance_field.h"
#include "core/model/spatial.h"
#include "core/model/triangle_mesh.h"

namespace igms {

enum class JointType { Revolute, Prismatic, Floating };

const char* jointTypeName(JointType t);

// Collision geometry, kept for the collision world (FCL) of later stages.
struct CollisionShape {
  enum class Kind { Box, Cylinder, Sphere, Mesh };
  Kind kind = Kind::Box;
  Vector3 size = Vector3::Zero();  // box: extents; cylinder: (radius, length, 0); sphere: (radius, 0, 0)
  std::string mesh_file;
  Vector3 mesh_scale = Vector3::Ones();
  // Collision meshes: the signed distance field the tip is tested against
  // (null for primitives, visuals, and meshes of descriptions read from text).
  std::shared_ptr<const DistanceField> field;
  std::shared_ptr<const TriangleMesh> triangles;  // the same mesh as triangles (the obstacle monitor's)
  SE3 placement;                   // in the frame of the link that owns it
};

// Visual geometry: what a viewer draws, a shape and its colour.
struct VisualShape {
  CollisionShape geometry;         // the shape; placement in the link frame
  Eigen::Vector4d rgba = Eigen::Vector4d(0.7, 0.7, 0.7, 1.0);
  bool has_color = false;          // false: the file gave no colour
};

// One URDF link: where its frame sits on a body.
struct Frame {
  std::string name;
  int body = -1;     // -1: the fixed root / world
  SE3 placement;     // link frame in the body frame
  std::vector<CollisionShape> collisions;
  std::vector<VisualShape> visuals;
};

struct Model {
  std::string name;
  std::string source;  // file the model came from, for messages

  int nq = 0;  // configuration size (floating base: 7 + joints)
  int nv = 0;  // velocity size (floating base: 6 + joints)
  int nb = 0;  // moving bodies = joints with coordinates

  bool floating_base = false;
  Vector3 gravity = Vector3(0.0, 0.0, -9.81);  // world frame

  // Per body (index = joint index: joint i moves body i).
  std::vector<std::string> joint_name;
  // The joint each one mimics in the URDF ("" : none). igms does not couple
  // them: a mimic joint is an independent coordinate (the load warns).
  std::vector<std::string> joint_mimic;
  std::vector<std::string> body_name;  // name of the URDF link that is the body frame
  std::vector<JointType> joint_type;
  std::vector<bool> joint_continuous;  // a revolute joint declared continuous (no limits)
  std::vector<int> parent;
  std::vector<int> q_index, v_index, joint_nv;
  std::vector<SE3> X_tree;         // joint frame in the parent body frame (fixed part)
  std::vector<Vector3> axis;       // unit joint axis in the body frame
  std::vector<int> axis_aligned;   // k when axis = +-e_k, else -1 (a faster joint placement)
  std::vector<SpatialInertia> inertia;  // in the body frame, fixed children merged in
  std::vector<std::vector<int>> children;

  // Per velocity coordinate.
  std::vector<int> dof_parent;     // nearest ancestor dof, -1 at a root: the sparsity of H
  std::vector<int> dof_run_start;  // r <= k with dof_parent[t] = t - 1 for r < t <= k
  std::vector<int> dof_subtree_end;  // one past t's last descendant: its subtree is t..end-1 (depth-first)
  std::vector<double> damping;     // N*m*s/rad or N*s/m, from <dynamics damping>
  std::vector<double> friction;    // Coulomb, from <dynamics friction>; kept, not applied
  std::vector<double> lower, upper, effort_limit, velocity_limit;  // inf when absent

  std::vector<Frame> frames;       // every URDF link
  std::string root_link;

  int frameIndex(const std::string& name) const;   // -1 when absent
  int jointIndex(const std::string& name) const;   // -1 when absent
  // The frame's pose in its body frame, and the body it rides on.
  const Frame& frame(int i) const { return frames[static_cast<size_t>(i)]; }
  double totalMass() const;
};

}  // namespace igms
