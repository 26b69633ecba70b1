#include "core/model_io/dh_loader.h"

#include <yaml-cpp/yaml.h>

#include <sstream>

namespace igms {
namespace {

struct Reader {
  std::string source;

  [[noreturn]] void fail(const YAML::Node& n, const std::string& what) const {
    throw ModelError(source + ":" + std::to_string(n.Mark().line + 1) + ": " + what);
  }
  double number(const YAML::Node& parent, const std::string& key, double fallback, bool required = false) const {
    const YAML::Node n = parent[key];
    if (!n) {
      if (required) fail(parent, "missing key '" + key + "'");
      return fallback;
    }
    try {
      return n.as<double>();
    } catch (const YAML::Exception&) {
      fail(n, "key '" + key + "': not a number");
    }
  }
  std::vector<double> numbers(const YAML::Node& parent, const std::string& key, size_t count) const {
    const YAML::Node n = parent[key];
    if (!n) return std::vector<double>(count, 0.0);
    if (!n.IsSequence() || n.size() != count)
      fail(n, "key '" + key + "': expected a list of " + std::to_string(count) + " numbers");
    std::vector<double> out;
    for (const auto& x : n) {
      try {
        out.push_back(x.as<double>());
      } catch (const YAML::Exception&) {
        fail(x, "key '" + key + "': not a number");
      }
    }
    return out;
  }
  std::string text(const YAML::Node& parent, const std::string& key, const std::string& fallback) const {
    const YAML::Node n = parent[key];
    if (!n) return fallback;
    if (!n.IsScalar()) fail(n, "key '" + key + "': expected text");
    return n.as<std::string>();
  }
};

SE3 rotX(double a) { return {Eigen::AngleAxisd(a, Vector3::UnitX()).toRotationMatrix(), Vector3::Zero()}; }
SE3 rotZ(double a) { return {Eigen::AngleAxisd(a, Vector3::UnitZ()).toRotationMatrix(), Vector3::Zero()}; }
SE3 transX(double a) { return {Matrix3::Identity(), Vector3(a, 0, 0)}; }
SE3 transZ(double d) { return {Matrix3::Identity(), Vector3(0, 0, d)}; }

// One row of the table: its joint (after the chain so far, `tail`) and its link, whose inertia the
// row gives in DH frame i. Moves `parent` and `tail` on to this row's link.
void addDhRow(const Reader& r, const YAML::Node& row, int index, bool modified, std::string& parent, SE3& tail,
              RobotDescription& d) {
  if (!row.IsMap()) r.fail(row, "each entry of 'links' must be a map");
  const std::string n = std::to_string(index);
  JointDescription j;
  j.name = r.text(row, "joint", "joint" + n);
  const std::string type = r.text(row, "type", "revolute");
  if (type != "revolute" && type != "prismatic") r.fail(row["type"], "type must be 'revolute' or 'prismatic'");
  const bool prismatic = type == "prismatic";
  j.type = prismatic ? JointDescription::Type::Prismatic : JointDescription::Type::Revolute;
  const double a = r.number(row, "a", 0.0, true);
  const double alpha = r.number(row, "alpha", 0.0, true);
  const double offset = r.number(row, "offset", 0.0);
  const double d_or_theta = prismatic ? r.number(row, "theta", 0.0) : r.number(row, "d", 0.0, true);
  // pre: constant part before the joint motion; post: after it (standard only).
  SE3 pre, post;
  if (modified) {
    pre = prismatic ? rotX(alpha) * transX(a) * rotZ(d_or_theta) * transZ(offset)
                    : rotX(alpha) * transX(a) * transZ(d_or_theta) * rotZ(offset);
  } else {
    pre = prismatic ? rotZ(d_or_theta) * transZ(offset) : rotZ(offset);
    post = prismatic ? transX(a) * rotX(alpha) : transZ(d_or_theta) * transX(a) * rotX(alpha);
  }
  j.origin = tail * pre;
  j.axis = Vector3::UnitZ();
  j.parent = parent;
  j.child = r.text(row, "link", "link" + n);
  j.damping = r.number(row, "damping", 0.0);
  j.friction = r.number(row, "friction", 0.0);
  if (const YAML::Node lim = row["limits"]) {
    const auto l = r.numbers(row, "limits", 2);
    j.lower = l[0];
    j.upper = l[1];
  }
  LinkDescription link;
  link.name = j.child;
  link.mass = r.number(row, "mass", 0.0);
  const auto com = r.numbers(row, "com", 3);
  const auto I = r.numbers(row, "inertia", 6);
  Matrix3 Ic;
  Ic << I[0], I[3], I[4], I[3], I[1], I[5], I[4], I[5], I[2];
  // com and inertia are given in DH frame i, which sits at `post` in the link frame.
  link.com = post.act(Vector3(com[0], com[1], com[2]));
  link.inertia = post.R * Ic * post.R.transpose();
  d.links.push_back(link);
  d.joints.push_back(j);
  parent = j.child;
  tail = post;
}

// A tool frame fixed on the last link, `tool_xyz` beyond its DH frame.
void addTool(const Reader& r, const YAML::Node& root, const std::string& tool, const std::string& parent,
             const SE3& tail, RobotDescription& d) {
  d.links.push_back(LinkDescription{tool, 0.0, Vector3::Zero(), Matrix3::Zero(), {}});
  JointDescription j;
  j.name = tool + "_joint";
  j.type = JointDescription::Type::Fixed;
  j.parent = parent;
  j.child = tool;
  const auto offset = r.numbers(root, "tool_xyz", 3);
  j.origin = tail * SE3{Matrix3::Identity(), Vector3(offset[0], offset[1], offset[2])};
  d.joints.push_back(j);
}

}  // namespace

RobotDescription parseDhDescription(const std::string& yaml, const std::string& source) {
  Reader r{source};
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    throw ModelError(source + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  if (!root.IsMap()) throw ModelError(source + ": expected a YAML map with 'links'");
  RobotDescription d;
  d.source = source;
  d.name = r.text(root, "name", "dh_robot");
  const std::string convention = r.text(root, "convention", "standard");
  if (convention != "standard" && convention != "modified")
    r.fail(root["convention"], "convention must be 'standard' or 'modified'");
  const bool modified = convention == "modified";
  const YAML::Node links = root["links"];
  if (!links || !links.IsSequence() || links.size() == 0) r.fail(root, "missing or empty 'links' list");

  d.links.push_back(LinkDescription{"base_link", 0.0, Vector3::Zero(), Matrix3::Zero(), {}});
  SE3 tail = SE3::Identity();
  if (const YAML::Node base = root["base"]) {
    const auto xyz = r.numbers(base, "xyz", 3), rpy = r.numbers(base, "rpy", 3);
    tail = fromXyzRpy(Vector3(xyz[0], xyz[1], xyz[2]), Vector3(rpy[0], rpy[1], rpy[2]));
  }
  std::string parent = "base_link";
  int index = 1;
  for (const YAML::Node& row : links) addDhRow(r, row, index++, modified, parent, tail, d);
  const std::string tool = r.text(root, "tool", "");
  if (!tool.empty()) addTool(r, root, tool, parent, tail, d);
  return d;
}

RobotDescription loadDhDescription(const std::string& path) {
  return parseDhDescription(readModelFile(path), path);
}

Model loadDhModel(const std::string& path, const BuildOptions& options, std::vector<std::string>* warnings) {
  return buildModel(loadDhDescription(path), options, warnings);
}

}  // namespace igms
