#include "server/app/session_description.h"

#include <algorithm>

#include "core/model_io/model_fingerprint.h"
#include "core/model_io/zlib_text.h"
#include "igms_build_info.h"

namespace igms {

namespace {

std::string modelTextOf(const RobotSpec& robot) {
  if (!robot.model_text.empty() || robot.model_path.empty()) return robot.model_text;
  try {
    return readModelFile(robot.model_path);
  } catch (const std::exception&) {
    return "";
  }
}

// A robot's files into a message that has the model and trajectory fields
// (session_info_t, robot_files_t: the same names).
template <typename Message>
void putRobotFiles(const RobotSpec& robot, Message* out) {
  out->model_path = robot.model_path;
  const std::string text = modelTextOf(robot);
  out->model_hash = text.empty() ? "unreadable" : textHash(text);
  out->model_size = static_cast<int32_t>(text.size());
  out->model_zlib = deflateText(text);
  out->model_zlib_size = static_cast<int32_t>(out->model_zlib.size());
  out->trajectory_path = robot.trajectory.file;
  out->trajectory_text = robot.trajectory.file_text;
}

template <typename Message>
void putMeshes(const std::vector<MeshFingerprint>& meshes, Message* out) {
  for (const MeshFingerprint& m : meshes) {
    out->mesh_uris.push_back(m.uri);
    out->mesh_hashes.push_back(m.hash);
  }
  out->nmeshes = static_cast<int32_t>(out->mesh_uris.size());
}

}  // namespace

session_info_t describeSession(const Simulation& sim, const std::string& clock) {
  const Scene& scene = sim.scene();
  session_info_t info;
  info.utime = 0;
  info.session_token = 0;
  info.build_version = IGMS_BUILD_VERSION;
  info.scene_path = scene.source;
  info.scene_text = scene.text;
  // The first robot's model file (a scene of free bodies has none; its shapes are in the scene).
  static const RobotSpec kNoRobot;
  const RobotSpec& robot = scene.robot() ? *scene.robot() : kNoRobot;
  putRobotFiles(robot, &info);
  putMeshes(meshFingerprints(sim.model(), robot.model_path.empty() ? scene.source : robot.model_path), &info);
  info.clock = clock;
  info.dt = scene.dt;
  return info;
}

session_files_t describeSessionFiles(const Simulation& sim) {
  const Scene& scene = sim.scene();
  const Model& model = sim.model();
  session_files_t files;
  files.utime = 0;
  files.session_token = 0;
  files.scene_path = scene.source;
  // The k-th robot is the model's k-th robot part (environment_model.h keeps the scene's order).
  std::vector<const ModelPart*> robot_parts;
  for (const ModelPart& part : model.parts)
    if (!part.free_body) robot_parts.push_back(&part);
  for (size_t k = 0; k < scene.robots.size(); ++k) {
    const RobotSpec& robot = scene.robots[k];
    robot_files_t r;
    r.robot = robot.name;
    putRobotFiles(robot, &r);
    r.nmeshes = 0;
    if (k < robot_parts.size())
      putMeshes(meshFingerprints(model, robot.model_path, robot_parts[k]->frame_begin, robot_parts[k]->frame_end), &r);
    files.robots.push_back(std::move(r));
  }
  files.nrobots = static_cast<int32_t>(files.robots.size());
  std::vector<MeshFingerprint> free_bodies;  // each distinct mesh once
  for (const ModelPart& part : model.parts) {
    if (!part.free_body) continue;
    for (MeshFingerprint& m : meshFingerprints(model, scene.source, part.frame_begin, part.frame_end))
      if (std::none_of(free_bodies.begin(), free_bodies.end(), [&](const MeshFingerprint& f) { return f.uri == m.uri; }))
        free_bodies.push_back(std::move(m));
  }
  files.nmeshes = 0;
  putMeshes(free_bodies, &files);
  return files;
}

}  // namespace igms
