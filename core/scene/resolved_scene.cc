#include "core/scene/resolved_scene.h"

#include "core/model/configuration.h"
#include "core/model_io/model_loader.h"

namespace igms {

namespace {

VectorX perJoint(const Scene& s, const VectorX& given, double scalar, const char* key, int nv) {
  if (!given.size()) return VectorX::Constant(nv, scalar);
  if (given.size() != nv)
    throw SceneError(s.source + ": controller." + key + " needs " + std::to_string(nv) + " entries");
  return given;
}

}  // namespace

ResolvedScene resolveScene(const Scene& scene) {
  ResolvedScene r;
  r.scene = scene;
  {
    Model loaded = scene.model_text.empty() ? loadModel(scene.model_path, scene.build)
                                            : parseModel(scene.model_text, scene.model_path, scene.build);
    for (const LinkCollision& lc : scene.collision) {
      const int f = loaded.frameIndex(lc.link);
      if (f < 0) throw SceneError(scene.source + ": robot.collision." + lc.link + ": no such link in " + scene.model_path);
      std::vector<CollisionShape>& shapes = loaded.frames[static_cast<size_t>(f)].collisions;
      if (!lc.keep_urdf) shapes.clear();
      shapes.insert(shapes.end(), lc.shapes.begin(), lc.shapes.end());
    }
    r.model = std::make_shared<const Model>(std::move(loaded));
  }
  const Model& m = *r.model;
  for (size_t i = 0; i < m.joint_mimic.size(); ++i)
    if (!m.joint_mimic[i].empty())
      r.warnings.push_back(scene.model_path + ": joint '" + m.joint_name[i] + "' mimics '" + m.joint_mimic[i] +
                           "': treated as an independent coordinate");
  if (scene.push.enabled) {
    // A link the tip passes through silently is the worst kind of no-op: say which.
    for (const Frame& f : m.frames) {
      if (f.body < 0 || m.body_name[static_cast<size_t>(f.body)] != f.name) continue;  // frames on a body: its own
      bool touchable = false;
      for (const CollisionShape& c : f.collisions) touchable |= c.kind != CollisionShape::Kind::Mesh || c.field;
      if (!touchable)
        r.warnings.push_back(scene.source + ": push is on, but link '" + f.name +
                             "' has no collision geometry the tip can touch: it passes through");
    }
  }
  r.q0 = scene.q0.size() ? scene.q0 : neutralConfiguration(m);
  r.v0 = scene.v0.size() ? scene.v0 : VectorX::Zero(m.nv);
  if (r.q0.size() != m.nq)
    throw SceneError(scene.source + ": initial.q has " + std::to_string(r.q0.size()) + " entries, the model needs " +
                     std::to_string(m.nq));
  if (r.v0.size() != m.nv)
    throw SceneError(scene.source + ": initial.v has " + std::to_string(r.v0.size()) + " entries, the model needs " +
                     std::to_string(m.nv));
  normalizeConfiguration(m, r.q0);
  r.kp = perJoint(scene, scene.kp, scene.kp_scalar, "kp", m.nv);
  r.kd = perJoint(scene, scene.kd, scene.kd_scalar, "kd", m.nv);
  if (scene.pull.enabled) {
    const std::string link = scene.pull.link.empty() ? m.frames.back().name : scene.pull.link;
    r.pull_frame = m.frameIndex(link);
    if (r.pull_frame < 0) throw SceneError(scene.source + ": interaction.pull.link: unknown link '" + link + "'");
  }
  if (m.floating_base && scene.trajectory.kind != TrajectorySpec::Kind::None)
    throw SceneError(scene.source + ": trajectory: a floating-base robot has no joint-space trajectory to follow");
  const std::vector<std::string>& columns = scene.trajectory.joint_names;
  if (!columns.empty() && columns != m.joint_name) {
    auto list = [](const std::vector<std::string>& names) {
      std::string out;
      for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
      return out;
    };
    throw SceneError(scene.trajectory.file + ": joints [" + list(columns) + "] are not the model's [" +
                     list(m.joint_name) + "] (" + scene.model_path + ")");
  }
  return r;
}

}  // namespace igms
