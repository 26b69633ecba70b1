// buildModel: RobotDescription -> Model. Validates, merges fixed joints into
// their parent body, orders bodies depth-first so that parent[i] < i.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdio>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/model/robot_description.h"

namespace igms {
namespace {

bool finite(const Vector3& v) { return v.allFinite(); }

std::string where(const RobotDescription& d) { return d.source.empty() ? "<robot>" : d.source; }

[[noreturn]] void fail(const RobotDescription& d, const std::string& what) {
  throw ModelError(where(d) + ": " + what);
}

const char* typeName(JointDescription::Type t) {
  switch (t) {
    case JointDescription::Type::Revolute: return "revolute";
    case JointDescription::Type::Continuous: return "continuous";
    case JointDescription::Type::Prismatic: return "prismatic";
    case JointDescription::Type::Fixed: return "fixed";
    case JointDescription::Type::Floating: return "floating";
    case JointDescription::Type::Planar: return "planar";
  }
  return "?";
}

void validateLink(const RobotDescription& d, const LinkDescription& l, std::vector<std::string>* warnings) {
  const std::string at = "link '" + l.name + "': ";
  if (!std::isfinite(l.mass)) fail(d, at + "mass is not finite");
  if (l.mass < 0.0) fail(d, at + "mass is negative (" + std::to_string(l.mass) + ")");
  if (!finite(l.com)) fail(d, at + "centre of mass is not finite");
  if (!l.inertia.allFinite()) fail(d, at + "inertia is not finite");
  const double scale = std::max(1.0, l.inertia.cwiseAbs().maxCoeff());
  if ((l.inertia - l.inertia.transpose()).cwiseAbs().maxCoeff() > 1e-12 * scale)
    fail(d, at + "inertia is not symmetric");
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Matrix3>(l.inertia).eigenvalues();
  if (ev.minCoeff() < -1e-12 * scale) {
    std::ostringstream s;
    s << at << "inertia is not positive semi-definite (eigenvalues " << ev.transpose() << ")";
    fail(d, s.str());
  }
  if (warnings && l.mass == 0.0 && l.inertia.cwiseAbs().maxCoeff() > 0.0)
    warnings->push_back(where(d) + ": warning: " + at + "rotational inertia without mass (a lumped rotor inertia?)");
  // Physical bodies satisfy the triangle inequality on principal moments;
  // classic published data (PUMA 560 link 3) does not, so this only warns.
  const double tol = 1e-9 * std::max(1e-300, ev.maxCoeff());
  if (warnings && ev.maxCoeff() > 0.0 && (ev(0) + ev(1) < ev(2) - tol)) {
    std::ostringstream s;
    s << where(d) << ": warning: " << at << "principal moments " << ev.transpose()
      << " break the triangle inequality (not a physical rigid body)";
    warnings->push_back(s.str());
  }
  for (const auto& c : l.collisions) {
    if (!finite(c.size) || !finite(c.placement.p) || !c.placement.R.allFinite())
      fail(d, at + "collision geometry has non-finite numbers");
  }
}

void validateJoint(const RobotDescription& d, const JointDescription& j) {
  const std::string at = "joint '" + j.name + "': ";
  if (!finite(j.origin.p) || !j.origin.R.allFinite()) fail(d, at + "origin is not finite");
  if (!finite(j.axis)) fail(d, at + "axis is not finite");
  if (std::isnan(j.lower) || std::isnan(j.upper) || std::isnan(j.effort) || std::isnan(j.velocity))
    fail(d, at + "limit is NaN");
  if (!std::isfinite(j.damping) || j.damping < 0.0) fail(d, at + "damping must be finite and >= 0");
  if (!std::isfinite(j.friction) || j.friction < 0.0) fail(d, at + "friction must be finite and >= 0");
  if (j.type == JointDescription::Type::Floating || j.type == JointDescription::Type::Planar)
    fail(d, at + "joint type '" + typeName(j.type) +
                "' is not supported inside a tree (a free root is chosen with the floating-base option)");
  const bool moving = j.type != JointDescription::Type::Fixed;
  if (moving && j.axis.norm() < 1e-12) fail(d, at + "axis is zero");
  if (j.parent == j.child) fail(d, at + "parent and child are the same link '" + j.parent + "'");
}

}  // namespace

const char* jointTypeName(JointType t) {
  switch (t) {
    case JointType::Revolute: return "revolute";
    case JointType::Prismatic: return "prismatic";
    case JointType::Floating: return "floating";
  }
  return "?";
}

namespace {

// The description's links and joints, checked and indexed: the tree they form and its one root.
struct TreeIndex {
  std::map<std::string, size_t> link_of;
  std::map<std::string, std::vector<size_t>> child_joints;  // parent link -> joints, in description order
  std::string root;
};

TreeIndex indexTree(const RobotDescription& d, std::vector<std::string>* warnings) {
  TreeIndex t;
  for (size_t i = 0; i < d.links.size(); ++i) {
    const auto& l = d.links[i];
    if (l.name.empty()) fail(d, "a link has no name");
    if (!t.link_of.emplace(l.name, i).second) fail(d, "duplicate link name '" + l.name + "'");
    validateLink(d, l, warnings);
  }
  std::set<std::string> joint_names;
  std::map<std::string, size_t> parent_joint_of;  // child link -> joint
  for (size_t k = 0; k < d.joints.size(); ++k) {
    const auto& j = d.joints[k];
    if (j.name.empty()) fail(d, "a joint has no name");
    if (!joint_names.insert(j.name).second) fail(d, "duplicate joint name '" + j.name + "'");
    validateJoint(d, j);
    if (!t.link_of.count(j.parent)) fail(d, "joint '" + j.name + "': unknown parent link '" + j.parent + "'");
    if (!t.link_of.count(j.child)) fail(d, "joint '" + j.name + "': unknown child link '" + j.child + "'");
    auto [it, fresh] = parent_joint_of.emplace(j.child, k);
    if (!fresh)
      fail(d, "link '" + j.child + "' has two parent joints ('" + d.joints[it->second].name + "' and '" + j.name + "')");
    t.child_joints[j.parent].push_back(k);
  }
  std::vector<std::string> roots;
  for (const auto& l : d.links)
    if (!parent_joint_of.count(l.name)) roots.push_back(l.name);
  if (roots.empty()) fail(d, "no root link: the joints form a cycle");
  if (roots.size() > 1) fail(d, "more than one root link ('" + roots[0] + "' and '" + roots[1] + "'): the links are not one tree");
  t.root = roots[0];
  return t;
}

// A body on its joint, below `parent` (-1: the world). \return its index.
int addBody(Model& m, const std::string& joint, const std::string& link, JointType type, int parent, const SE3& X_tree,
            const Vector3& axis) {
  m.joint_name.push_back(joint);
  m.body_name.push_back(link);
  m.joint_type.push_back(type);
  m.joint_continuous.push_back(false);
  m.parent.push_back(parent);
  m.X_tree.push_back(X_tree);
  m.axis.push_back(axis);
  int aligned = -1;
  for (int k = 0; k < 3; ++k)
    if (std::abs(std::abs(axis[k]) - 1.0) < 1e-15 && axis.squaredNorm() < 1.0 + 1e-15) aligned = k;
  m.axis_aligned.push_back(aligned);
  m.inertia.push_back(SpatialInertia::Zero());
  m.children.emplace_back();
  if (parent >= 0) m.children[static_cast<size_t>(parent)].push_back(m.nb);
  const int nv = type == JointType::Floating ? 6 : 1;
  m.q_index.push_back(m.nq);
  m.v_index.push_back(m.nv);
  m.joint_nv.push_back(nv);
  m.nq += type == JointType::Floating ? 7 : 1;
  m.nv += nv;
  return m.nb++;
}

// Depth-first walk from the root: each link lands on a body with a placement in it, a moving joint
// starts a body, a fixed one keeps its child on its parent's. With one parent per link and a single
// root, the walk cannot loop; links it does not reach sit on a cycle.
struct LinkWalk {
  const RobotDescription& d;
  const TreeIndex& tree;
  std::vector<std::string>* warnings;
  Model& m;
  std::vector<const JointDescription*> joint_of_body;  // per body (null: the floating root)
  std::set<std::string> visited;

  void visit(const std::string& name, int body, const SE3& placement) {
    visited.insert(name);
    const LinkDescription& link = d.links[tree.link_of.at(name)];
    m.frames.push_back(Frame{link.name, body, placement, link.collisions, link.visuals});
    const bool has_inertia = link.mass > 0.0 || link.inertia.cwiseAbs().maxCoeff() > 0.0;
    if (body >= 0 && has_inertia) {
      m.inertia[static_cast<size_t>(body)] +=
          SpatialInertia::fromMassComInertia(link.mass, link.com, link.inertia).transformedBy(placement);
    } else if (body < 0 && has_inertia && warnings) {
      warnings->push_back(where(d) + ": note: link '" + link.name + "' is fixed to the world; its mass is ignored");
    }
    auto it = tree.child_joints.find(name);
    if (it == tree.child_joints.end()) return;
    for (size_t k : it->second) {
      const JointDescription& j = d.joints[k];
      const SE3 X = placement * j.origin;
      if (j.type == JointDescription::Type::Fixed) {
        visit(j.child, body, X);
        continue;
      }
      const JointType type = j.type == JointDescription::Type::Prismatic ? JointType::Prismatic : JointType::Revolute;
      const int b = addBody(m, j.name, j.child, type, body, X, j.axis.normalized());
      joint_of_body.resize(static_cast<size_t>(b + 1), nullptr);
      joint_of_body[static_cast<size_t>(b)] = &j;
      m.joint_continuous[static_cast<size_t>(b)] = j.type == JointDescription::Type::Continuous;
      visit(j.child, b, SE3::Identity());
    }
  }
};

// Per-dof arrays: each dof's parent dof, its joint's damping, friction and limits.
void fillDofs(Model& m, const std::vector<const JointDescription*>& joint_of_body) {
  const double inf = std::numeric_limits<double>::infinity();
  m.dof_parent.assign(static_cast<size_t>(m.nv), -1);
  m.damping.assign(static_cast<size_t>(m.nv), 0.0);
  m.friction.assign(static_cast<size_t>(m.nv), 0.0);
  m.lower.assign(static_cast<size_t>(m.nv), -inf);
  m.upper.assign(static_cast<size_t>(m.nv), inf);
  m.effort_limit.assign(static_cast<size_t>(m.nv), inf);
  m.velocity_limit.assign(static_cast<size_t>(m.nv), inf);
  for (int i = 0; i < m.nb; ++i) {
    const int v0 = m.v_index[i];
    const int p = m.parent[i];
    const int above = p < 0 ? -1 : m.v_index[p] + m.joint_nv[p] - 1;
    for (int k = 0; k < m.joint_nv[i]; ++k) m.dof_parent[v0 + k] = k == 0 ? above : v0 + k - 1;
    const JointDescription* j = joint_of_body[static_cast<size_t>(i)];
    if (!j) continue;
    const bool continuous = j->type == JointDescription::Type::Continuous;
    m.damping[v0] = j->damping;
    m.friction[v0] = j->friction;
    m.lower[v0] = continuous ? -inf : j->lower;
    m.upper[v0] = continuous ? inf : j->upper;
    m.effort_limit[v0] = j->effort;
    m.velocity_limit[v0] = j->velocity;
  }
  m.dof_run_start.assign(static_cast<size_t>(m.nv), 0);
  for (int k = 0; k < m.nv; ++k)
    m.dof_run_start[k] = (k > 0 && m.dof_parent[k] == k - 1) ? m.dof_run_start[k - 1] : k;
  m.dof_subtree_end.resize(static_cast<size_t>(m.nv));
  for (int k = 0; k < m.nv; ++k) m.dof_subtree_end[k] = k + 1;
  for (int k = m.nv - 1; k >= 0; --k)  // children come after their parent: leaves first
    if (m.dof_parent[k] >= 0)
      m.dof_subtree_end[m.dof_parent[k]] = std::max(m.dof_subtree_end[m.dof_parent[k]], m.dof_subtree_end[k]);
}

// A joint whose subtree carries no inertia along its axis makes H singular: said so.
void warnSingularJoints(const RobotDescription& d, const Model& m, std::vector<std::string>* warnings) {
  if (!warnings) return;
  std::vector<SpatialInertia> Ic(m.inertia);
  for (int i = m.nb - 1; i > 0; --i)
    if (m.parent[i] >= 0) Ic[m.parent[i]] += Ic[i].transformedBy(m.X_tree[i]);
  for (int i = 0; i < m.nb; ++i) {
    double along = 0.0;
    if (m.joint_type[i] == JointType::Revolute) along = m.axis[i].dot(Ic[i].Io * m.axis[i]);
    if (m.joint_type[i] == JointType::Prismatic) along = Ic[i].m;
    if (m.joint_type[i] == JointType::Floating) along = std::min(Ic[i].m, Ic[i].inertiaAboutCom().eigenvalues().real().minCoeff());
    if (!(along > 0.0))
      warnings->push_back(where(d) + ": warning: joint '" + m.joint_name[i] +
                          "' moves no mass or inertia along its axis: H is singular, forward dynamics will fail");
  }
}

// Mimic joints (grippers' fingers): kept as independent coordinates, said so.
void recordMimics(const RobotDescription& d, Model& m, std::vector<std::string>* warnings) {
  m.joint_mimic.assign(static_cast<size_t>(m.nb), "");
  for (const JointDescription& j : d.joints) {
    if (j.mimic.empty()) continue;
    for (int i = 0; i < m.nb; ++i)
      if (m.joint_name[static_cast<size_t>(i)] == j.name) m.joint_mimic[static_cast<size_t>(i)] = j.mimic;
    if (warnings) {
      std::ostringstream w;
      w << where(d) << ": warning: joint '" << j.name << "' mimics '" << j.mimic << "' (q = " << j.mimic_multiplier
        << " q_" << j.mimic << " + " << j.mimic_offset << "): igms treats it as an independent coordinate";
      warnings->push_back(w.str());
    }
  }
}

}  // namespace

Model buildModel(const RobotDescription& d, const BuildOptions& options, std::vector<std::string>* warnings) {
  if (d.links.empty()) fail(d, "no links");
  if (!options.gravity.allFinite()) fail(d, "gravity is not finite");
  const TreeIndex tree = indexTree(d, warnings);
  Model m;
  m.name = d.name;
  m.source = d.source;
  m.floating_base = options.floating_base;
  m.gravity = options.gravity;
  m.root_link = tree.root;
  LinkWalk walk{d, tree, warnings, m, {}, {}};
  if (options.floating_base) {
    addBody(m, "root_joint", m.root_link, JointType::Floating, -1, SE3::Identity(), Vector3::Zero());
    walk.joint_of_body.push_back(nullptr);
  }
  walk.visit(m.root_link, options.floating_base ? 0 : -1, SE3::Identity());
  for (const auto& l : d.links)
    if (!walk.visited.count(l.name))
      fail(d, "link '" + l.name + "' is not reachable from the root '" + m.root_link + "': the joints form a cycle");
  fillDofs(m, walk.joint_of_body);
  warnSingularJoints(d, m, warnings);
  m.parts.push_back(ModelPart{"", false, 0, m.nb, 0, m.nv, 0, m.nq, 0, static_cast<int>(m.frames.size())});
  recordMimics(d, m, warnings);
  return m;
}

std::string readModelFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw ModelError(path + ": cannot open the file");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string textHash(const std::string& text) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

int Model::frameIndex(const std::string& n) const {
  for (size_t i = 0; i < frames.size(); ++i)
    if (frames[i].name == n) return static_cast<int>(i);
  return -1;
}

int Model::jointIndex(const std::string& n) const {
  for (size_t i = 0; i < joint_name.size(); ++i)
    if (joint_name[i] == n) return static_cast<int>(i);
  return -1;
}

int Model::partOfBody(int b) const {
  for (size_t k = 0; k < parts.size(); ++k)
    if (b >= parts[k].body_begin && b < parts[k].body_end) return static_cast<int>(k);
  return -1;
}

int Model::partOfFrame(int f) const {
  for (size_t k = 0; k < parts.size(); ++k)
    if (f >= parts[k].frame_begin && f < parts[k].frame_end) return static_cast<int>(k);
  return -1;
}

double Model::totalMass() const {
  double s = 0.0;
  for (const auto& I : inertia) s += I.m;
  return s;
}

}  // namespace igms
