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

// Collision geometry: what the tip touches, what bodies touch each other with (core/contact), and
// what the obstacle monitor (FCL) tests. Cylinders and capsules lie along their frame's z axis; a
// plane is its frame's z = 0 with the solid below (the ground).
struct CollisionShape {
  enum class Kind { Box, Cylinder, Sphere, Mesh, Capsule, Plane };  // names, sizes: core/geometry/shape_kind.h
  Kind kind = Kind::Box;
  // box: extents; cylinder and capsule: (radius, length of the axis between the caps' centres, 0);
  // sphere: (radius, 0, 0); plane: unused
  Vector3 size = Vector3::Zero();
  std::string mesh_file;
  Vector3 mesh_scale = Vector3::Ones();
  // Collision meshes: the signed distance field the tip is tested against
  // (null for primitives, visuals, and meshes of descriptions read from text).
  std::shared_ptr<const DistanceField> field;
  std::shared_ptr<const TriangleMesh> triangles;  // the same mesh as triangles (the obstacle monitor's)
  // Meshes: points spread over the surface (shape frame), what the contact layer tests against the
  // other shape of a pair (core/model_io/mesh_fields fills them with the field; empty otherwise).
  std::shared_ptr<const std::vector<Vector3>> samples;
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

// One tree of a model: a robot (the paper's MultiBody) or a free body (FreeBody: one body on a
// floating joint). A model from one robot file is one part; a scene's environment model is its
// robots and free bodies side by side (environment_model.h), each its own tree.
struct ModelPart {
  std::string name;        // the scene's name for it ("" for the robot of a one-robot model)
  bool free_body = false;
  int body_begin = 0, body_end = 0;    // its bodies
  int dof_begin = 0, dof_end = 0;      // its velocity coordinates
  int q_begin = 0, q_end = 0;          // its configuration coordinates
  int frame_begin = 0, frame_end = 0;  // its frames (links), those fixed to the world included
  int nv() const { return dof_end - dof_begin; }
  int nq() const { return q_end - q_begin; }
};

struct Model {
  std::string name;
  std::string source;  // file the model came from, for messages

  int nq = 0;  // configuration size (floating base: 7 + joints)
  int nv = 0;  // velocity size (floating base: 6 + joints)
  int nb = 0;  // moving bodies = joints with coordinates

  bool floating_base = false;  // the first part's root is free (a floating base)
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
  std::string root_link;           // the first part's root link
  std::vector<ModelPart> parts;    // the trees, in body order (one for a robot file)

  int frameIndex(const std::string& name) const;   // -1 when absent
  int jointIndex(const std::string& name) const;   // -1 when absent
  // The frame's pose in its body frame, and the body it rides on.
  const Frame& frame(int i) const { return frames[static_cast<size_t>(i)]; }
  double totalMass() const;
  // The part that body b (>= 0) or frame f belongs to.
  int partOfBody(int b) const;
  int partOfFrame(int f) const;
};

}  // namespace igms
