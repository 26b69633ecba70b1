#include <cstdio>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/geometry/shape_kind.h"
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

std::string join(const std::string& dir, const std::string& path) {
  if (path.empty() || path[0] == '/' || dir.empty()) return path;
  return dir + "/" + path;
}

// "box, cylinder, sphere or capsule" (and mesh): the kinds a scene may name, from the table.
std::string shapeNames(bool allow_mesh) {
  std::vector<std::string> names;
  for (const ShapeKindInfo& k : shapeKinds())
    if (k.primitive) names.push_back(k.name);
  if (allow_mesh) names.push_back(shapeKindName(CollisionShape::Kind::Mesh));
  std::string out;
  for (size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return out;
}

// A shape with its pose: obstacles and free bodies (in the world), robot.collision (in a link's frame).
// Meshes (allow_mesh): file (from the scene's folder, base_dir, unless absolute or a package://)
// and scale; their fields come with resolveScene.
CollisionShape primitive(const Reader& r, const YAML::Node& o, const std::string& where, bool allow_mesh = false,
                         const std::string& base_dir = "") {
  CollisionShape c;
  const std::string shape = r.text(o, "shape", "");
  const ShapeKindInfo* kind = shapeKindNamed(shape);
  if (kind && kind->primitive) {
    c.kind = kind->kind;
    for (const ShapeDimension& d : kind->dimensions) {
      if (!d.key) continue;
      if (d.count == 1) {
        c.size[d.at] = r.positive(o, d.key, 0.0, where);
        continue;
      }
      const std::string at = where + "." + d.key;
      if (!o[d.key]) r.fail(o, at, "missing");
      c.size.segment(d.at, d.count) = r.numbers(o[d.key], at, d.count);
      if ((c.size.segment(d.at, d.count).array() <= 0.0).any()) r.fail(o[d.key], at, "must be positive");
    }
  } else if (kind && kind->kind == CollisionShape::Kind::Mesh && allow_mesh) {
    c.kind = CollisionShape::Kind::Mesh;
    const std::string file = r.text(o, "file", "");
    if (file.empty()) r.fail(o, where + ".file", "missing (a mesh file: STL, OBJ, Collada)");
    c.mesh_file = file.rfind("package://", 0) == 0
                      ? file
                      : std::filesystem::absolute(join(base_dir, file)).lexically_normal().string();
    if (o["scale"]) c.mesh_scale = r.numbers(o["scale"], where + ".scale", 3);
    if ((c.mesh_scale.array() <= 0.0).any()) r.fail(o["scale"], where + ".scale", "must be positive");
  } else {
    r.fail(o["shape"] ? o["shape"] : o, where + ".shape", "must be " + shapeNames(allow_mesh));
  }
  c.placement = pose(r, o);
  return c;
}

}  // namespace

namespace {

// robot.collision (or a robots: entry's collision:): per link, shapes instead of the URDF's; the item
// from_urdf keeps the URDF's too.
std::vector<LinkCollision> linkCollisions(const Reader& r, const YAML::Node& collision, const std::string& at) {
  std::vector<LinkCollision> out;
  if (!collision.IsMap()) r.fail(collision, at, "expected a map of link names");
  for (const auto& kv : collision) {
    LinkCollision lc;
    lc.link = kv.first.as<std::string>();
    const std::string where = at + "." + lc.link;
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
    out.push_back(lc);
  }
  return out;
}

void parseInitial(const Reader& r, const YAML::Node& init, const std::string& at, RobotSpec& robot) {
  r.onlyKeys(init, at, {"q", "v"});
  if (init["q"]) robot.q0 = r.numbers(init["q"], at + ".q");
  if (init["v"]) robot.v0 = r.numbers(init["v"], at + ".v");
}

void parseTrajectory(const Reader& r, const YAML::Node& t, const std::string& at, const std::string& source,
                     const std::string& base_dir, const std::map<std::string, std::string>* files, TrajectorySpec& out) {
  r.onlyKeys(t, at, {"kind", "frame", "target", "duration", "waypoints", "file"});
  const std::string kind = r.text(t, "kind", "none");
  if (kind == "cartesian_line") {
    out.kind = TrajectorySpec::Kind::CartesianLine;
    out.frame = r.text(t, "frame", "");
    if (!t["target"]) r.fail(t, at + ".target", "missing");
    out.target = r.vector3(t, "target", Vector3::Zero());
    out.duration = r.positive(t, "duration", 0.0, at);
  } else if (kind == "joint_waypoints" || kind == "file") {
    out.kind = TrajectorySpec::Kind::JointWaypoints;
    YAML::Node file_doc;  // keeps the loaded file alive while its nodes are read
    std::string where = source;
    if (kind == "file") {
      where = join(base_dir, r.text(t, "file", ""));
      const auto given = files ? files->find(where) : std::map<std::string, std::string>::const_iterator{};
      if (files && given != files->end()) {
        out.file_text = given->second;
      } else {
        std::ifstream in(where);
        if (!in) r.fail(t["file"] ? t["file"] : t, at + ".file", "cannot read '" + where + "'");
        std::stringstream content;
        content << in.rdbuf();
        out.file_text = content.str();
      }
      out.file = where;
      try {
        file_doc = YAML::Load(out.file_text);
      } catch (const YAML::Exception& e) {
        r.fail(t["file"] ? t["file"] : t, at + ".file", "cannot read '" + where + "': " + e.msg);
      }
    }
    // Bound once: yaml-cpp's operator= on a node writes through it instead of rebinding.
    const YAML::Node points = kind == "file" ? file_doc["waypoints"] : t["waypoints"];
    if (kind == "file" && file_doc["joints"]) {
      const YAML::Node names = file_doc["joints"];
      if (!names.IsSequence()) r.fail(names, at + ".file: joints", "must be a list of joint names in " + where);
      for (const auto& n : names) out.joint_names.push_back(n.as<std::string>());
    }
    if (!points || !points.IsSequence() || points.size() < 2)
      r.fail(t, at + ".waypoints", "needs a list of two or more {t, q} in " + where);
    for (const auto& p : points) {
      out.times.push_back(r.number(p, "t", NAN));
      if (!std::isfinite(out.times.back())) r.fail(p, at + ".waypoints[].t", "missing");
      if (!p["q"]) r.fail(p, at + ".waypoints[].q", "missing");
      out.waypoints.push_back(r.numbers(p["q"], at + ".waypoints[].q"));
    }
    for (size_t k = 1; k < out.times.size(); ++k)
      if (!(out.times[k] > out.times[k - 1])) r.fail(t, at + ".waypoints", "times must increase");
  } else if (kind != "none") {
    r.fail(t["kind"], at + ".kind", "must be none, joint_waypoints, file or cartesian_line");
  }
}

void parseController(const Reader& r, const YAML::Node& c, const std::string& at, RobotSpec& robot) {
  r.onlyKeys(c, at, {"kind", "kp", "kd", "hold_damping"});
  const std::string kind = r.text(c, "kind", "computed_torque");
  if (kind == "computed_torque") robot.controller = ControllerKind::ComputedTorque;
  else if (kind == "pd") robot.controller = ControllerKind::Pd;
  else r.fail(c["kind"], at + ".kind", "must be computed_torque or pd");
  auto gain = [&](const char* key, double& scalar, VectorX& per_joint) {
    const YAML::Node g = c[key];
    if (!g) return;
    if (g.IsSequence()) per_joint = r.numbers(g, at + "." + key);
    else scalar = r.number(c, key, scalar);
    if (scalar < 0.0 || (per_joint.size() && (per_joint.array() < 0.0).any())) r.fail(g, at + "." + key, "must be >= 0");
  };
  gain("kp", robot.kp_scalar, robot.kp);
  gain("kd", robot.kd_scalar, robot.kd);
  robot.hold_damping = r.number(c, "hold_damping", robot.hold_damping);
}

std::string materialName(const Reader& r, const YAML::Node& n, const std::string& at, const Scene& s) {
  const std::string name = r.text(n, "material", "");
  if (!name.empty() && !s.materials.count(name)) {
    std::string known;
    for (const auto& [k, v] : s.materials) known += (known.empty() ? "" : ", ") + k;
    r.fail(n["material"], at + ".material", "unknown material '" + name + "' (the scene's: " + known + ")");
  }
  return name;
}

// One function per top-level key, called in the order the keys' checks depend on (materials before
// anything that names one; robots before their per-robot keys; the coupling after the push).
void parseMaterials(const Reader& r, const YAML::Node& root, Scene& s) {
  s.materials["default"] = Material{};
  const YAML::Node materials = root["materials"];
  if (!materials) return;
  if (!materials.IsMap()) r.fail(materials, "materials", "expected a map of material names");
  for (const auto& kv : materials) {
    const std::string name = kv.first.as<std::string>();
    const std::string at = "materials." + name;
    r.onlyKeys(kv.second, at, {"friction", "restitution", "rolling", "torsion"});
    Material m;
    m.friction = r.number(kv.second, "friction", m.friction);
    if (m.friction < 0.0) r.fail(kv.second["friction"], at + ".friction", "must be >= 0");
    m.restitution = r.number(kv.second, "restitution", m.restitution);
    if (m.restitution < 0.0 || m.restitution > 1.0) r.fail(kv.second["restitution"], at + ".restitution", "must be in [0, 1]");
    m.rolling = r.number(kv.second, "rolling", m.rolling);
    if (!(m.rolling >= 0.0)) r.fail(kv.second["rolling"], at + ".rolling", "must be >= 0 (m)");
    m.torsion = r.number(kv.second, "torsion", m.torsion);
    if (!(m.torsion >= 0.0)) r.fail(kv.second["torsion"], at + ".torsion", "must be >= 0 (m)");
    s.materials[name] = m;
  }
}

// Where the scene's files are: relative model and trajectory paths, and the files a log carries.
struct SceneFiles {
  const std::string& source;
  const std::string& base_dir;
  const std::map<std::string, std::string>* files;
};

// One robot: `robot:` (short_form: its initial state, trajectory and controller are top-level keys) or
// an entry of `robots:`.
void parseRobot(const Reader& r, const YAML::Node& n, const std::string& at, bool short_form, const SceneFiles& f,
                Scene& s) {
  RobotSpec spec;
  if (short_form) r.onlyKeys(n, at, {"model", "floating_base", "collision", "base", "material"});
  else
    r.onlyKeys(n, at, {"name", "model", "floating_base", "collision", "base", "material", "initial", "trajectory",
                       "controller"});
  const std::string model = r.text(n, "model", "");
  if (model.empty()) r.fail(n, at + ".model", "missing");
  spec.model_path = join(f.base_dir, model);
  spec.floating_base = r.flag(n, "floating_base", false);
  if (const YAML::Node base = n["base"]) {
    r.onlyKeys(base, at + ".base", {"xyz", "rpy"});
    spec.base = pose(r, base);
  }
  if (const YAML::Node collision = n["collision"]) spec.collision = linkCollisions(r, collision, at + ".collision");
  spec.material = materialName(r, n, at, s);
  if (!short_form) {
    spec.name = r.text(n, "name", "robot" + std::to_string(s.robots.size()));
    if (spec.name.empty() || spec.name.find('/') != std::string::npos) r.fail(n, at + ".name", "must be a name without '/'");
    for (const RobotSpec& other : s.robots)
      if (other.name == spec.name) r.fail(n, at + ".name", "another robot is named '" + spec.name + "'");
    if (const YAML::Node init = n["initial"]) parseInitial(r, init, at + ".initial", spec);
    if (const YAML::Node t = n["trajectory"])
      parseTrajectory(r, t, at + ".trajectory", f.source, f.base_dir, f.files, spec.trajectory);
    if (const YAML::Node c = n["controller"]) parseController(r, c, at + ".controller", spec);
  }
  s.robots.push_back(spec);
}

void parseRobots(const Reader& r, const YAML::Node& root, const SceneFiles& f, Scene& s) {
  const YAML::Node robot = root["robot"], robots = root["robots"];
  if (robot && robots) r.fail(robots, "robots", "give robot: (one) or robots: (several), not both");
  if (robot) {
    parseRobot(r, robot, "robot", true, f, s);
    RobotSpec& spec = s.robots.back();
    if (const YAML::Node init = root["initial"]) parseInitial(r, init, "initial", spec);
    if (const YAML::Node t = root["trajectory"])
      parseTrajectory(r, t, "trajectory", f.source, f.base_dir, f.files, spec.trajectory);
    if (const YAML::Node c = root["controller"]) parseController(r, c, "controller", spec);
    return;
  }
  for (const char* key : {"initial", "trajectory", "controller"})
    if (root[key]) r.fail(root[key], key, std::string("belongs to a robot: robot: (one) or inside each of robots:"));
  if (robots) {
    if (!robots.IsSequence() || robots.size() == 0) r.fail(robots, "robots", "expected a list of robots");
    for (size_t k = 0; k < robots.size(); ++k) parseRobot(r, robots[k], "robots[" + std::to_string(k) + "]", false, f, s);
  }
}

void parseBodies(const Reader& r, const YAML::Node& root, const std::string& base_dir, Scene& s) {
  const YAML::Node bodies = root["bodies"];
  if (!bodies) return;
  if (!bodies.IsSequence()) r.fail(bodies, "bodies", "expected a list of free bodies");
  for (size_t k = 0; k < bodies.size(); ++k) {
    const YAML::Node b = bodies[k];
    const std::string at = "bodies[" + std::to_string(k) + "]";
    r.onlyKeys(b, at, {"name", "shape", "size", "radius", "length", "file", "scale", "mass", "density", "inertia",
                       "xyz", "rpy", "v", "w", "material", "color"});
    FreeBodySpec body;
    body.name = r.text(b, "name", "body" + std::to_string(k));
    if (body.name.empty() || body.name.find('/') != std::string::npos) r.fail(b, at + ".name", "must be a name without '/'");
    for (const FreeBodySpec& other : s.bodies)
      if (other.name == body.name) r.fail(b, at + ".name", "another body is named '" + body.name + "'");
    body.shape = primitive(r, b, at, true, base_dir);
    body.pose = body.shape.placement;
    body.shape.placement = SE3::Identity();
    if (b["mass"] && b["density"]) r.fail(b["density"], at + ".density", "give mass or density, not both");
    if (b["mass"]) body.mass = r.positive(b, "mass", 1.0, at);
    body.density = r.positive(b, "density", body.density, at);
    if (const YAML::Node inertia = b["inertia"]) {
      const VectorX i = r.numbers(inertia, at + ".inertia", 6);
      body.has_inertia = true;
      body.inertia << i[0], i[3], i[4], i[3], i[1], i[5], i[4], i[5], i[2];
    }
    body.velocity = r.vector3(b, "v", Vector3::Zero());
    body.angular_velocity = r.vector3(b, "w", Vector3::Zero());
    body.material = materialName(r, b, at, s);
    if (b["color"]) {
      const VectorX c = r.numbers(b["color"], at + ".color", 4);
      body.rgba = c;
    }
    s.bodies.push_back(body);
  }
}

void parseGround(const Reader& r, const YAML::Node& root, Scene& s) {
  const YAML::Node ground = root["ground"];
  if (!ground) return;
  if (ground.IsScalar()) {
    s.ground.enabled = r.flag(root, "ground", false);
    return;
  }
  r.onlyKeys(ground, "ground", {"height", "rpy", "material"});
  s.ground.enabled = true;
  s.ground.pose = fromXyzRpy(Vector3(0.0, 0.0, r.number(ground, "height", 0.0)), r.vector3(ground, "rpy", Vector3::Zero()));
  s.ground.material = materialName(r, ground, "ground", s);
}

void parseObstacles(const Reader& r, const YAML::Node& root, const std::string& base_dir, Scene& s) {
  const YAML::Node obstacles = root["obstacles"];
  if (!obstacles) return;
  if (!obstacles.IsSequence()) r.fail(obstacles, "obstacles", "expected a list");
  for (const auto& o : obstacles) {
    r.onlyKeys(o, "obstacles[]", {"name", "shape", "size", "radius", "length", "file", "scale", "xyz", "rpy", "solid",
                                  "material"});
    Obstacle ob;
    ob.name = r.text(o, "name", "obstacle" + std::to_string(s.obstacles.size()));
    ob.shape = primitive(r, o, "obstacles[]", true, base_dir);
    ob.solid = r.flag(o, "solid", false);
    ob.material = materialName(r, o, "obstacles[]", s);
    s.obstacles.push_back(ob);
  }
}

void parseContact(const Reader& r, const YAML::Node& root, Scene& s) {
  const YAML::Node c = root["contact"];
  if (!c) return;
  r.onlyKeys(c, "contact", {"self_collision", "margin", "iterations", "tolerance", "bounce_velocity", "max_contacts"});
  ContactSettings& k = s.contact;
  k.self_collision = r.flag(c, "self_collision", k.self_collision);
  k.margin = r.positive(c, "margin", k.margin, "contact");
  k.iterations = static_cast<int>(r.positive(c, "iterations", k.iterations, "contact"));
  k.tolerance = r.positive(c, "tolerance", k.tolerance, "contact");
  k.bounce_velocity = r.number(c, "bounce_velocity", k.bounce_velocity);
  if (k.bounce_velocity < 0.0) r.fail(c["bounce_velocity"], "contact.bounce_velocity", "must be >= 0 (m/s)");
  k.max_contacts = static_cast<int>(r.number(c, "max_contacts", 0));
  if (k.max_contacts < 0) r.fail(c["max_contacts"], "contact.max_contacts", "must be >= 0 (0: from the scene's size)");
}

void parsePush(const Reader& r, const YAML::Node& p, Scene& s) {
  r.onlyKeys(p, "interaction.push", {"k_p", "max_force", "tip_radius", "friction"});
  s.push.enabled = true;
  s.push.k_p = r.positive(p, "k_p", s.push.k_p, "interaction.push");
  s.push.max_force = r.positive(p, "max_force", s.push.max_force, "interaction.push");
  s.push.tip_radius = r.positive(p, "tip_radius", s.push.tip_radius, "interaction.push");
  s.push.friction = r.number(p, "friction", s.push.friction);
  if (!(s.push.friction >= 0.0)) r.fail(p["friction"], "interaction.push.friction", "must be >= 0");
}

// The push's virtual coupling: its spring (the push's k_p, given once) and its damper.
void parseCoupling(const Reader& r, const YAML::Node& in, Scene& s) {
  const YAML::Node c = in["coupling"];
  r.onlyKeys(c, "interaction.coupling", {"k", "b"});
  if (!s.push.enabled) r.fail(c, "interaction.coupling", "couples the push: needs interaction.push");
  if (c["k"]) {
    const double k = r.positive(c, "k", s.push.k_p, "interaction.coupling");
    if (in["push"]["k_p"] && k != s.push.k_p)
      r.fail(c["k"], "interaction.coupling.k", "is interaction.push.k_p (the same spring): give one of them");
    s.push.k_p = k;
  }
  s.push.b = kCouplingTime * s.push.k_p;
  s.push.b = r.number(c, "b", s.push.b);
  if (s.push.b < 0.0) r.fail(c["b"], "interaction.coupling.b", "must be >= 0 (N s/m)");
}

void parsePull(const Reader& r, const YAML::Node& p, Scene& s) {
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

void parseInteraction(const Reader& r, const YAML::Node& root, Scene& s) {
  const YAML::Node in = root["interaction"];
  if (!in) return;
  r.onlyKeys(in, "interaction", {"push", "pull", "coupling", "workspace"});
  if (const YAML::Node p = in["push"]) parsePush(r, p, s);
  s.push.b = kCouplingTime * s.push.k_p;
  if (in["coupling"]) parseCoupling(r, in, s);
  if (const YAML::Node p = in["pull"]) parsePull(r, p, s);
  if (const YAML::Node w = in["workspace"]) {
    r.onlyKeys(w, "interaction.workspace", {"scale", "offset"});
    s.workspace_scale = r.positive(w, "scale", 1.0, "interaction.workspace");
    s.workspace_offset = r.vector3(w, "offset", Vector3::Zero());
  }
}

void parseSimulation(const Reader& r, const YAML::Node& root, Scene& s) {
  const YAML::Node sim = root["simulation"];
  if (!sim) return;
  r.onlyKeys(sim, "simulation", {"integrator", "dt", "rate_hz", "joint_damping", "joint_limits"});
  const std::string integ = r.text(sim, "integrator", "linearly_implicit");
  if (!parseIntegrator(integ, &s.integrator)) r.fail(sim["integrator"], "simulation.integrator", "must be semi_implicit_euler, rk4 or linearly_implicit");
  s.dt = r.positive(sim, "dt", s.dt, "simulation");
  s.rate_hz = r.positive(sim, "rate_hz", 1.0 / s.dt, "simulation");
  s.joint_damping = r.flag(sim, "joint_damping", true);
  s.joint_limits = r.flag(sim, "joint_limits", true);
}

// The coupling is passive at the scene's rate only with damper enough for the spring's hold.
void checkCouplingPassive(const Reader& r, const YAML::Node& root, const Scene& s) {
  if (!s.push.enabled || s.push.b >= s.push.k_p / (2.0 * s.rate_hz)) return;
  const YAML::Node in = root["interaction"];
  const YAML::Node at = in["coupling"] && in["coupling"]["b"] ? in["coupling"]["b"] : in["coupling"] ? in["coupling"] : in["push"];
  char what[200];
  std::snprintf(what, sizeof what,
                "%g N s/m is below k T / 2 = %g N s/m at the scene's %g Hz (Colgate and Schenkel): the coupling "
                "would not be passive",
                s.push.b, s.push.k_p / (2.0 * s.rate_hz), s.rate_hz);
  r.fail(at, "interaction.coupling.b", what);
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
             {"name", "robot", "robots", "gravity", "initial", "obstacles", "trajectory", "controller", "interaction",
              "simulation", "bodies", "ground", "materials", "contact"});
  Scene s;
  s.source = source;
  s.text = yaml;
  s.name = r.text(root, "name", "scene");
  s.gravity = r.vector3(root, "gravity", Vector3(0, 0, -9.81));
  parseMaterials(r, root, s);
  parseRobots(r, root, SceneFiles{source, base_dir, files}, s);
  parseBodies(r, root, base_dir, s);
  if (s.robots.empty() && s.bodies.empty()) r.fail(root, "robot", "missing (robot:, robots: or bodies: says what moves)");
  parseGround(r, root, s);
  parseObstacles(r, root, base_dir, s);
  parseContact(r, root, s);
  parseInteraction(r, root, s);
  parseSimulation(r, root, s);
  checkCouplingPassive(r, root, s);
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
