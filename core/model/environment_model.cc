#include "core/model/environment_model.h"

namespace igms {

Model emptyEnvironment(const std::string& name, const std::string& source, const Vector3& gravity) {
  Model m;
  m.name = name;
  m.source = source;
  m.gravity = gravity;
  return m;
}

void appendTree(Model& env, const Model& tree, const std::string& part_name, const std::string& prefix, const SE3& base,
                bool free_body) {
  ModelPart part;
  part.name = part_name;
  part.free_body = free_body;
  part.body_begin = env.nb;
  part.dof_begin = env.nv;
  part.q_begin = env.nq;
  part.frame_begin = static_cast<int>(env.frames.size());
  const int b0 = env.nb, d0 = env.nv, q0 = env.nq;
  auto shift = [](int i, int by) { return i < 0 ? i : i + by; };
  for (int i = 0; i < tree.nb; ++i) {
    env.joint_name.push_back(prefix + tree.joint_name[i]);
    env.joint_mimic.push_back(tree.joint_mimic.empty() || tree.joint_mimic[i].empty() ? "" : prefix + tree.joint_mimic[i]);
    env.body_name.push_back(prefix + tree.body_name[i]);
    env.joint_type.push_back(tree.joint_type[i]);
    env.joint_continuous.push_back(tree.joint_continuous[i]);
    env.parent.push_back(shift(tree.parent[i], b0));
    env.q_index.push_back(tree.q_index[i] + q0);
    env.v_index.push_back(tree.v_index[i] + d0);
    env.joint_nv.push_back(tree.joint_nv[i]);
    // A fixed base's root joints hang from the world: they move with the base. A floating root's
    // placement is its coordinates'.
    const bool root = tree.parent[i] < 0 && tree.joint_type[i] != JointType::Floating;
    env.X_tree.push_back(root ? base * tree.X_tree[i] : tree.X_tree[i]);
    env.axis.push_back(tree.axis[i]);
    env.axis_aligned.push_back(tree.axis_aligned[i]);
    env.inertia.push_back(tree.inertia[i]);
    std::vector<int> children;
    for (int c : tree.children[i]) children.push_back(c + b0);
    env.children.push_back(children);
  }
  for (int k = 0; k < tree.nv; ++k) {
    env.dof_parent.push_back(shift(tree.dof_parent[k], d0));
    env.dof_run_start.push_back(tree.dof_run_start[k] + d0);
    env.dof_subtree_end.push_back(tree.dof_subtree_end[k] + d0);
    env.damping.push_back(tree.damping[k]);
    env.friction.push_back(tree.friction[k]);
    env.lower.push_back(tree.lower[k]);
    env.upper.push_back(tree.upper[k]);
    env.effort_limit.push_back(tree.effort_limit[k]);
    env.velocity_limit.push_back(tree.velocity_limit[k]);
  }
  for (const Frame& f : tree.frames) {
    Frame g = f;
    g.name = prefix + f.name;
    g.body = shift(f.body, b0);
    if (f.body < 0) g.placement = base * f.placement;
    env.frames.push_back(g);
  }
  if (env.parts.empty()) {
    env.root_link = prefix + tree.root_link;
    env.floating_base = tree.floating_base;
  }
  env.nb += tree.nb;
  env.nv += tree.nv;
  env.nq += tree.nq;
  part.body_end = env.nb;
  part.dof_end = env.nv;
  part.q_end = env.nq;
  part.frame_end = static_cast<int>(env.frames.size());
  env.parts.push_back(part);
}

std::vector<std::string> coordinateNames(const Model& model) {
  std::vector<std::string> out;
  int robots = 0;
  for (const ModelPart& part : model.parts) robots += !part.free_body;
  for (const ModelPart& part : model.parts) {
    if (part.free_body) {
      for (const char* c : {"x", "y", "z", "qw", "qx", "qy", "qz"}) out.push_back(part.name + "." + c);
      continue;
    }
    const std::string prefix = robots > 1 || !part.name.empty() ? part.name + "." : "";
    for (int k = 0; k < part.nq(); ++k) out.push_back(prefix + "q" + std::to_string(k));
  }
  return out;
}

FreeBodyState freeBodyState(const ModelPart& part, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  const int iq = part.q_begin, iv = part.dof_begin;
  const Matrix3 R = Eigen::Quaterniond(q[iq + 3], q[iq + 4], q[iq + 5], q[iq + 6]).normalized().toRotationMatrix();
  return FreeBodyState{q.segment<3>(iq), R, R * v.segment<3>(iv), R * v.segment<3>(iv + 3)};
}

}  // namespace igms
