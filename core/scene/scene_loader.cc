#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <sstream>

#include "core/scene/scene.h"

namespace igms {
namespace {

struct Reader {
  std::string source;

  [[noreturn]] void fail(const YAML::Node& n, const std::string& key, const std::string& what) const {
    throw SceneError(source + ":" + std::to_string(n.Mark().line + 1) + ": " + key + ": " + what);
  }
  double number(const YAML::Node& parent, const std::string& key, double fallback) const {
    const YAML::Node n = parent[key];
    if (!n) return fallback;
    double x;
    try {
      x = n.as<double>();
    } catch (const YAML::Exception&) {
      fail(n, key, "not a number");
    }
    if (!std::isfinite(x)) fail(n, key, "not finite");
    return x;
  }
  double positive(const YAML::Node& parent, const std::string& key, double fallback,
                  const std::string& path = "") const {
    const double x = number(parent, key, fallback);
    if (!(x > 0.0)) fail(parent[key] ? parent[key] : parent, path.empty() ? key : path + "." + key, "must be positive");
    return x;
  }
  bool flag(const YAML::Node& parent, const std::string& key, bool fallback) const {
    const YAML::Node n = parent[key];
    if (!n) return fallback;
    try {
      return n.as<bool>();
    } catch (const YAML::Exception&) {
      fail(n, key, "expected true or false");
    }
  }
  std::string text(const YAML::Node& parent, const std::string& key, const std::string& fallback) const {
    const YAML::Node n = parent[key];
    if (!n) return fallback;
    if (!n.IsScalar()) fail(n, key, "expected text");
    return n.as<std::string>();
  }
  VectorX numbers(const YAML::Node& n, const std::string& key, int count = -1) const {
    if (!n.IsSequence()) fail(n, key, "expected a list of numbers");
    if (count >= 0 && static_cast<int>(n.size()) != count)
      fail(n, key, "expected " + std::to_string(count) + " numbers, got " + std::to_string(n.size()));
    VectorX out(static_cast<int>(n.size()));
    for (size_t i = 0; i < n.size(); ++i) {
      try {
        out[static_cast<int>(i)] = n[i].as<double>();
      } catch (const YAML::Exception&) {
        fail(n[i], key, "not a number");
      }
      if (!std::isfinite(out[static_cast<int>(i)])) fail(n[i], key, "not finite");
    }
    return out;
  }
  Vector3 vector3(const YAML::Node& parent, const std::string& key, const Vector3& fallback) const {
    const YAML::Node n = parent[key];
    if (!n) return fallback;
    return numbers(n, key, 3);
  }
  void onlyKeys(const YAML::Node& map, const std::string& where, std::initializer_list<const char*> keys) const {
    if (!map.IsMap()) fail(map, where, "expected a map");
    for (const auto& kv : map) {
      const std::string k = kv.first.as<std::string>();
      bool known = false;
      for (const char* allowed : keys) known |= k == allowed;
      if (!known) fail(kv.first, where + "." + k, "unknown key");
    }
  }
};

SE3 pose(const Reader& r, const YAML::Node& n) {
  return fromXyzRpy(r.vector3(n, "xyz", Vector3::Zero()), r.vector3(n, "rpy", Vector3::Zero()));
}

// A box, sphere or cylinder with its pose: obstacles (in the world) and robot.collision (in a link's frame).
CollisionShape primitive(const Reader& r, const YAML::Node& o, const std::string& where) {
  CollisionShape c;
  const std::string shape = r.text(o, "shape", "");
  if (shape == "box") {
    c.kind = CollisionShape::Kind::Box;
    if (!o["size"]) r.fail(o, where + ".size", "missing");
    c.size = r.numbers(o["size"], where + ".size", 3);
    if ((c.size.array() <= 0.0).any()) r.fail(o["size"], where + ".size", "must be positive");
  } else if (shape == "sphere") {
    c.kind = CollisionShape::Kind::Sphere;
    c.size = Vector3(r.positive(o, "radius", 0.0, where), 0, 0);
  } else if (shape == "cylinder") {
    c.kind = CollisionShape::Kind::Cylinder;
    c.size = Vector3(r.positive(o, "radius", 0.0, where), r.positive(o, "length", 0.0, where), 0);
  } else {
    r.fail(o["shape"] ? o["shape"] : o, where + ".shape", "must be box, sphere or cylinder");
  }
  c.placement = pose(r, o);
  return c;
}

std::string join(const std::string& dir, const std::string& path) {
  if (path.empty() || path[0] == '/' || dir.empty()) return path;
  return dir + "/" + path;
}

}  // namespace

Scene parseScene(const std::string& yaml, const std::string& source, const std::string& base_dir,
                 const std::map<std::string, std::string>* files) {
  Reader r{source};
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::Exception& e) {
    throw SceneError(source + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  if (!root.IsMap()) throw SceneError(source + ": expected a YAML map");
  r.onlyKeys(root, "scene",
             {"name", "robot", "gravity", "initial", "obstacles", "trajectory", "controller", "interaction",
              "simulation"});
  Scene s;
  s.source = source;
  s.text = yaml;
  s.name = r.text(root, "name", "scene");

  const YAML::Node robot = root["robot"];
  if (!robot) r.fail(root, "robot", "missing");
  r.onlyKeys(robot, "robot", {"model", "floating_base", "collision"});
  const std::string model = r.text(robot, "model", "");
  if (model.empty()) r.fail(robot, "robot.model", "missing");
  s.model_path = join(base_dir, model);
  s.build.floating_base = r.flag(robot, "floating_base", false);
  if (const YAML::Node collision = robot["collision"]) {
    // Per link: its collision shapes instead of the URDF's; the item from_urdf keeps the URDF's too.
    if (!collision.IsMap()) r.fail(collision, "robot.collision", "expected a map of link names");
    for (const auto& kv : collision) {
      LinkCollision lc;
      lc.link = kv.first.as<std::string>();
      const std::string where = "robot.collision." + lc.link;
      if (!kv.second.IsSequence()) r.fail(kv.second, where, "expected a list of shapes (and from_urdf)");
      for (const auto& item : kv.second) {
        if (item.IsScalar() && item.as<std::string>() == "from_urdf") {
          lc.keep_urdf = true;
          continue;
        }
        if (!item.IsMap()) r.fail(item, where + "[]", "expected a shape or from_urdf");
        r.onlyKeys(item, where + "[]", {"shape", "size", "radius", "length", "xyz", "rpy"});
        lc.shapes.push_back(primitive(r, item, where + "[]"));
      }
      s.collision.push_back(lc);
    }
  }
  s.build.gravity = r.vector3(root, "gravity", Vector3(0, 0, -9.81));

  if (const YAML::Node init = root["initial"]) {
    r.onlyKeys(init, "initial", {"q", "v"});
    if (init["q"]) s.q0 = r.numbers(init["q"], "initial.q");
    if (init["v"]) s.v0 = r.numbers(init["v"], "initial.v");
  }

  if (const YAML::Node obstacles = root["obstacles"]) {
    if (!obstacles.IsSequence()) r.fail(obstacles, "obstacles", "expected a list");
    for (const auto& o : obstacles) {
      r.onlyKeys(o, "obstacles[]", {"name", "shape", "size", "radius", "length", "xyz", "rpy"});
      Obstacle ob;
      ob.name = r.text(o, "name", "obstacle" + std::to_string(s.obstacles.size()));
      ob.shape = primitive(r, o, "obstacles[]");
      s.obstacles.push_back(ob);
    }
  }

  if (const YAML::Node t = root["trajectory"]) {
    r.onlyKeys(t, "trajectory", {"kind", "frame", "target", "duration", "waypoints", "file"});
    const std::string kind = r.text(t, "kind", "none");
    if (kind == "cartesian_line") {
      s.trajectory.kind = TrajectorySpec::Kind::CartesianLine;
      s.trajectory.frame = r.text(t, "frame", "");
      if (!t["target"]) r.fail(t, "trajectory.target", "missing");
      s.trajectory.target = r.vector3(t, "target", Vector3::Zero());
      s.trajectory.duration = r.positive(t, "duration", 0.0, "trajectory");
    } else if (kind == "joint_waypoints" || kind == "file") {
      s.trajectory.kind = TrajectorySpec::Kind::JointWaypoints;
      YAML::Node file_doc;  // keeps the loaded file alive while its nodes are read
      std::string where = source;
      if (kind == "file") {
        where = join(base_dir, r.text(t, "file", ""));
        const auto given = files ? files->find(where) : std::map<std::string, std::string>::const_iterator{};
        if (files && given != files->end()) {
          s.trajectory.file_text = given->second;
        } else {
          std::ifstream in(where);
          if (!in) r.fail(t["file"] ? t["file"] : t, "trajectory.file", "cannot read '" + where + "'");
          std::stringstream content;
          content << in.rdbuf();
          s.trajectory.file_text = content.str();
        }
        s.trajectory.file = where;
        try {
          file_doc = YAML::Load(s.trajectory.file_text);
        } catch (const YAML::Exception& e) {
          r.fail(t["file"] ? t["file"] : t, "trajectory.file", "cannot read '" + where + "': " + e.msg);
        }
      }
      // Bound once: yaml-cpp's operator= on a node writes through it instead of rebinding.
      const YAML::Node points = kind == "file" ? file_doc["waypoints"] : t["waypoints"];
      if (kind == "file" && file_doc["joints"]) {
        const YAML::Node names = file_doc["joints"];
        if (!names.IsSequence()) r.fail(names, "trajectory.file: joints", "must be a list of joint names in " + where);
        for (const auto& n : names) s.trajectory.joint_names.push_back(n.as<std::string>());
      }
      if (!points || !points.IsSequence() || points.size() < 2)
        r.fail(t, "trajectory.waypoints", "needs a list of two or more {t, q} in " + where);
      for (const auto& p : points) {
        s.trajectory.times.push_back(r.number(p, "t", NAN));
        if (!std::isfinite(s.trajectory.times.back())) r.fail(p, "trajectory.waypoints[].t", "missing");
        if (!p["q"]) r.fail(p, "trajectory.waypoints[].q", "missing");
        s.trajectory.waypoints.push_back(r.numbers(p["q"], "trajectory.waypoints[].q"));
      }
      for (size_t k = 1; k < s.trajectory.times.size(); ++k)
        if (!(s.trajectory.times[k] > s.trajectory.times[k - 1]))
          r.fail(t, "trajectory.waypoints", "times must increase");
    } else if (kind != "none") {
      r.fail(t["kind"], "trajectory.kind", "must be none, joint_waypoints, file or cartesian_line");
    }
  }

  if (const YAML::Node c = root["controller"]) {
    r.onlyKeys(c, "controller", {"kp", "kd", "hold_damping"});
    auto gain = [&](const char* key, double& scalar, VectorX& per_joint) {
      const YAML::Node g = c[key];
      if (!g) return;
      if (g.IsSequence()) per_joint = r.numbers(g, std::string("controller.") + key);
      else scalar = r.number(c, key, scalar);
      if (scalar < 0.0 || (per_joint.size() && (per_joint.array() < 0.0).any()))
        r.fail(g, std::string("controller.") + key, "must be >= 0");
    };
    gain("kp", s.kp_scalar, s.kp);
    gain("kd", s.kd_scalar, s.kd);
    s.hold_damping = r.number(c, "hold_damping", s.hold_damping);
  }

  if (const YAML::Node in = root["interaction"]) {
    r.onlyKeys(in, "interaction", {"push", "pull", "workspace"});
    if (const YAML::Node p = in["push"]) {
      r.onlyKeys(p, "interaction.push", {"k_p", "max_force", "tip_radius"});
      s.push.enabled = true;
      s.push.k_p = r.positive(p, "k_p", s.push.k_p, "interaction.push");
      s.push.max_force = r.positive(p, "max_force", s.push.max_force, "interaction.push");
      s.push.tip_radius = r.positive(p, "tip_radius", s.push.tip_radius, "interaction.push");
    }
    if (const YAML::Node p = in["pull"]) {
      r.onlyKeys(p, "interaction.pull", {"k", "b", "max_force", "max_stretch", "link", "point", "k_rot", "b_rot",
                                               "max_torque", "max_angle"});
      s.pull.enabled = true;
      s.pull.k = r.positive(p, "k", s.pull.k, "interaction.pull");
      s.pull.b = r.number(p, "b", s.pull.b);
      if (s.pull.b < 0.0) r.fail(p["b"], "interaction.pull.b", "must be >= 0");
      s.pull.max_force = r.positive(p, "max_force", s.pull.max_force, "interaction.pull");
      s.pull.max_stretch = r.positive(p, "max_stretch", s.pull.max_stretch, "interaction.pull");
      s.pull.link = r.text(p, "link", "");
      s.pull.point = r.vector3(p, "point", Vector3::Zero());
      s.pull.k_rot = r.number(p, "k_rot", s.pull.k_rot);
      if (s.pull.k_rot < 0.0) r.fail(p["k_rot"], "interaction.pull.k_rot", "must be >= 0 (N m/rad)");
      s.pull.b_rot = r.number(p, "b_rot", s.pull.b_rot);
      if (s.pull.b_rot < 0.0) r.fail(p["b_rot"], "interaction.pull.b_rot", "must be >= 0 (N m s/rad)");
      s.pull.max_torque = r.positive(p, "max_torque", s.pull.max_torque, "interaction.pull");
      s.pull.max_angle = r.positive(p, "max_angle", s.pull.max_angle, "interaction.pull");
      if (s.pull.max_angle > 3.14159) r.fail(p["max_angle"], "interaction.pull.max_angle", "must be <= pi (rad)");
    }
    if (const YAML::Node w = in["workspace"]) {
      r.onlyKeys(w, "interaction.workspace", {"scale", "offset"});
      s.workspace_scale = r.positive(w, "scale", 1.0, "interaction.workspace");
      s.workspace_offset = r.vector3(w, "offset", Vector3::Zero());
    }
  }

  if (const YAML::Node sim = root["simulation"]) {
    r.onlyKeys(sim, "simulation", {"integrator", "dt", "rate_hz", "joint_damping", "joint_limits"});
    const std::string integ = r.text(sim, "integrator", "linearly_implicit");
    if (!parseIntegrator(integ, &s.integrator)) r.fail(sim["integrator"], "simulation.integrator", "must be semi_implicit_euler, rk4 or linearly_implicit");
    s.dt = r.positive(sim, "dt", s.dt, "simulation");
    s.rate_hz = r.positive(sim, "rate_hz", 1.0 / s.dt, "simulation");
    s.joint_damping = r.flag(sim, "joint_damping", true);
    s.joint_limits = r.flag(sim, "joint_limits", true);
  }
  return s;
}

Scene loadScene(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw SceneError(path + ": cannot open the file");
  std::stringstream ss;
  ss << in.rdbuf();
  const size_t slash = path.find_last_of('/');
  return parseScene(ss.str(), path, slash == std::string::npos ? "." : path.substr(0, slash));
}

}  // namespace igms
