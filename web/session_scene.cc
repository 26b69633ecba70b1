#include "web/session_scene.h"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/geometry/shape_kind.h"
#include "core/geometry/shape_surface.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/model_io/resource_path.h"
#include "core/scene/resolved_scene.h"
#include "core/simulation/simulation.h"

namespace igms::web {
namespace {

using nlohmann::json;

json vec(const Vector3& v) { return json::array({v.x(), v.y(), v.z()}); }

json pose(const SE3& X) {
  Eigen::Quaterniond q(X.R);
  return {{"p", vec(X.p)}, {"q", json::array({q.w(), q.x(), q.y(), q.z()})}};
}

// The kinds the page draws from their name and size (web/page/robot_view.js), and a mesh from its
// file; any other kind goes as its surface's triangles, so that a new kind needs no line here.
bool pageDrawsItself(CollisionShape::Kind kind) {
  using Kind = CollisionShape::Kind;
  return kind == Kind::Box || kind == Kind::Sphere || kind == Kind::Cylinder || kind == Kind::Plane ||
         kind == Kind::Mesh;
}

// Vertices at float precision (a micrometre at the scale of a room), flat, and the triangles' indices.
json surface(const CollisionShape& s) {
  const TriangleMesh m = shapeSurface(s);
  json vertices = json::array(), triangles = json::array();
  for (const Vector3& v : m.vertices)
    for (int i = 0; i < 3; ++i) vertices.push_back(static_cast<float>(v[i]));
  for (const auto& t : m.triangles)
    for (int i : t) triangles.push_back(i);
  return {{"vertices", vertices}, {"triangles", triangles}};
}

json shape(const CollisionShape& s, const std::string& model_file,
           const std::function<std::string(const std::string&)>& serve) {
  json j = pose(s.placement);
  j["kind"] = shapeKindName(s.kind);  // a plane is its z = 0, solid below
  if (shapeKind(s.kind).primitive) j["size"] = vec(s.size);  // as CollisionShape::size holds it
  if (!pageDrawsItself(s.kind)) j["surface"] = surface(s);
  if (s.kind == CollisionShape::Kind::Mesh) {
    j["scale"] = vec(s.mesh_scale);
    const ResourceResolution r = resolveResource(s.mesh_file, model_file);
    if (r.path.empty()) {
      j["missing"] = s.mesh_file;  // the page draws a marker and the HUD names it
    } else {
      j["url"] = serve(r.path);
    }
  }
  return j;
}

// The frame a stick to this link starts from: its parent body's frame, or
// its own body's frame for a link fixed to a body.
int stickParent(const Model& m, int f) {
  const Frame& frame = m.frame(f);
  if (frame.body < 0) return frame.name == m.root_link ? -1 : m.frameIndex(m.root_link);
  const auto b = static_cast<size_t>(frame.body);
  if (m.body_name[b] != frame.name) return m.frameIndex(m.body_name[b]);
  const int pb = m.parent[b];
  return pb >= 0 ? m.frameIndex(m.body_name[static_cast<size_t>(pb)]) : m.frameIndex(m.root_link);
}

// The file a part's meshes are named relative to: its robot's (several robots
// come from several files, robots first in the model; the environment model's
// own source is the first's).
const std::string& sourceOfPart(const ResolvedScene& r, int part) {
  const auto& robots = r.scene.robots;
  if (part >= 0 && part < static_cast<int>(robots.size())) return robots[static_cast<size_t>(part)].model_path;
  return r.model->source;
}

json links(const ResolvedScene& r, const std::function<std::string(const std::string&)>& serve) {
  const Model& m = *r.model;
  json out = json::array();
  for (int f = 0; f < static_cast<int>(m.frames.size()); ++f) {
    const Frame& frame = m.frame(f);
    const int part = m.partOfFrame(f);
    const std::string& source = sourceOfPart(r, part);
    json l = {{"name", frame.name}, {"parent", stickParent(m, f)}};
    l["free_body"] = part >= 0 && m.parts[static_cast<size_t>(part)].free_body;
    json shapes = json::array();
    if (!frame.visuals.empty()) {
      for (const VisualShape& v : frame.visuals) {
        json s = shape(v.geometry, source, serve);
        if (v.has_color) s["rgba"] = json::array({v.rgba[0], v.rgba[1], v.rgba[2], v.rgba[3]});
        shapes.push_back(s);
      }
      l["geometry"] = "visual";
    } else if (!frame.collisions.empty()) {
      for (const CollisionShape& c : frame.collisions) shapes.push_back(shape(c, source, serve));
      l["geometry"] = "collision";
    } else {
      l["geometry"] = "none";
    }
    l["shapes"] = shapes;
    out.push_back(l);
  }
  return out;
}

// The nominal path of the traced link: forward kinematics along the nominal
// joint trajectory, 200 samples evenly over [0, *end].
json nominalPath(const ResolvedScene& r, int traced, double* end_time) {
  json path = json::array();
  *end_time = 0.0;
  Simulation sim(r);
  const int robot = traced < 0 ? -1 : sim.robotOfFrame(traced);
  if (robot < 0 || sim.robot(robot).nominal().empty()) return path;
  const Model& m = *r.model;
  const ModelPart& part = sim.robot(robot).part();
  const PiecewisePolynomial& nominal = sim.robot(robot).nominal();
  Data data(m);
  VectorX q = r.q0, qr(part.nq()), qd(part.nq()), qdd(part.nq());  // the others where the scene puts them
  const double end = *end_time = nominal.endTime();
  constexpr int kSamples = 200;
  for (int k = 0; k <= kSamples; ++k) {
    nominal.evaluate(end * k / kSamples, qr, qd, qdd);
    q.segment(part.q_begin, part.nq()) = qr;
    forwardKinematics(m, data, q);
    path.push_back(vec(framePose(m, data, traced).p));
  }
  return path;
}

}  // namespace

SessionScene describeSession(const session_info_t& info,
                             const std::function<std::string(const std::string&)>& serve) {
  SessionScene out;
  out.key = info.scene_path + "|" + info.model_hash + "|" + std::to_string(info.session_token);
  json hello = {{"type", "hello"},      {"scene_path", info.scene_path}, {"clock", info.clock},
                {"dt", info.dt},        {"build", info.build_version},    {"links", json::array()},
                {"obstacles", json::array()}, {"nominal_path", json::array()}, {"error", ""}};
  try {
    std::string dir = std::filesystem::path(info.scene_path).parent_path().string();
    if (dir.empty()) dir = ".";
    const ResolvedScene r = resolveScene(parseScene(info.scene_text, info.scene_path, dir));
    const Model& m = *r.model;
    const Scene& s = r.scene;
    hello["scene"] = s.name;
    hello["links"] = links(r, serve);
    json obstacles = json::array();
    for (const Obstacle& o : s.obstacles) {
      json j = shape(o.shape, m.source, serve);
      j["name"] = o.name;
      j["solid"] = o.solid;  // solid ones touch (drawn opaque); ghosts are only monitored
      obstacles.push_back(j);
    }
    if (s.ground.enabled) {  // the ground plane, drawn as one more solid obstacle
      CollisionShape plane;
      plane.kind = CollisionShape::Kind::Plane;
      plane.placement = s.ground.pose;
      json j = shape(plane, m.source, serve);
      j["name"] = "ground";
      j["solid"] = true;
      obstacles.push_back(j);
    }
    hello["obstacles"] = obstacles;
    int traced = r.pull_frame;
    if (const RobotSpec* robot = s.robot(); robot && robot->trajectory.kind == TrajectorySpec::Kind::CartesianLine)
      traced = m.frameIndex((robot->name.empty() ? "" : robot->name + "/") + robot->trajectory.frame);
    if (traced < 0) traced = static_cast<int>(m.frames.size()) - 1;
    hello["traced_link"] = traced;
    double nominal_end = 0.0;
    hello["nominal_path"] = nominalPath(r, traced, &nominal_end);
    hello["nominal_end"] = nominal_end;
    hello["push"] = {{"enabled", s.push.enabled}, {"k_p", s.push.k_p}, {"tip_radius", s.push.tip_radius},
                     {"max_force", s.push.max_force}};
    hello["pull"] = {{"enabled", s.pull.enabled}, {"k", s.pull.k}, {"b", s.pull.b},
                     {"link", r.pull_frame}, {"point", vec(s.pull.point)}};
    out.nlinks = static_cast<int>(m.frames.size());
  } catch (const std::exception& e) {
    out.error = e.what();
    hello["error"] = out.error;
  }
  // Strings from the bus may be any bytes: invalid UTF-8 becomes U+FFFD rather than an exception.
  out.hello_json = hello.dump(-1, ' ', false, json::error_handler_t::replace);
  return out;
}

}  // namespace igms::web
