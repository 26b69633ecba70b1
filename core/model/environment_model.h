// The environment as one model (the paper's Environment): every robot and
// every free body is a tree of its own in the same Model, so the dynamics,
// integrators and the rest run on a scene as they run on one robot. The
// inertia matrix is block-diagonal across the trees, and the sparse
// factorisation keeps it so (dof_parent never crosses from one tree to another).
#pragma once

#include <string>
#include <vector>

#include "core/model/model.h"

namespace igms {

// An empty model for trees to be appended to.
Model emptyEnvironment(const std::string& name, const std::string& source, const Vector3& gravity);

// Appends `tree` (a one-part model: a robot's, or a free body's) as a new part: its bodies, dofs,
// coordinates and frames come after env's, its joint, body and frame names get `prefix` in front,
// and its links fixed to the world (a fixed base's root) sit at `base` in the world. A floating
// root's pose is in the coordinates, not here.
void appendTree(Model& env, const Model& tree, const std::string& part_name, const std::string& prefix, const SE3& base,
                bool free_body);

// A name for each coordinate of q, as the tools' CSV columns give them: q0... for the robot of a
// one-robot model, ROBOT.q0... with several robots (or a named one), and NAME.x NAME.y NAME.z NAME.qw
// NAME.qx NAME.qy NAME.qz for a free body's pose.
std::vector<std::string> coordinateNames(const Model& model);

// A free body's state in the world: the pose of its frame (its centre of mass) and its linear and
// angular velocity, from its floating joint's q (position, quaternion w first) and v (body frame).
struct FreeBodyState {
  Vector3 p;
  Matrix3 R;
  Vector3 v, w;
};
FreeBodyState freeBodyState(const ModelPart& part, const Eigen::VectorXd& q, const Eigen::VectorXd& v);

}  // namespace igms
