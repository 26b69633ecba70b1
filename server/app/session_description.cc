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
  info.model_path = robot.model_path;
  const std::string model_text = modelTextOf(robot);
  info.model_hash = model_text.empty() ? "unreadable" : textHash(model_text);
  info.model_size = static_cast<int32_t>(model_text.size());
  info.model_zlib = deflateText(model_text);
  info.model_zlib_size = static_cast<int32_t>(info.model_zlib.size());
  info.trajectory_path = robot.trajectory.file;
  info.trajectory_text = robot.trajectory.file_text;
  for (const MeshFingerprint& m : meshFingerprints(sim.model(), robot.model_path.empty() ? scene.source : robot.model_path)) {
    info.mesh_uris.push_back(m.uri);
    info.mesh_hashes.push_back(m.hash);
  }
  info.nmeshes = static_cast<int32_t>(info.mesh_uris.size());
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
    r.model_path = robot.model_path;
    const std::string text = modelTextOf(robot);
    r.model_hash = text.empty() ? "unreadable" : textHash(text);
    r.model_size = static_cast<int32_t>(text.size());
    r.model_zlib = deflateText(text);
    r.model_zlib_size = static_cast<int32_t>(r.model_zlib.size());
    r.trajectory_path = robot.trajectory.file;
    r.trajectory_text = robot.trajectory.file_text;
    if (k < robot_parts.size()) {
      for (const MeshFingerprint& m :
           meshFingerprints(model, robot.model_path, robot_parts[k]->frame_begin, robot_parts[k]->frame_end)) {
        r.mesh_uris.push_back(m.uri);
        r.mesh_hashes.push_back(m.hash);
      }
    }
    r.nmeshes = static_cast<int32_t>(r.mesh_uris.size());
    files.robots.push_back(std::move(r));
  }
  files.nrobots = static_cast<int32_t>(files.robots.size());
  for (const ModelPart& part : model.parts) {
    if (!part.free_body) continue;
    for (const MeshFingerprint& m : meshFingerprints(model, scene.source, part.frame_begin, part.frame_end)) {
      if (std::find(files.mesh_uris.begin(), files.mesh_uris.end(), m.uri) != files.mesh_uris.end()) continue;
      files.mesh_uris.push_back(m.uri);
      files.mesh_hashes.push_back(m.hash);
    }
  }
  files.nmeshes = static_cast<int32_t>(files.mesh_uris.size());
  return files;
}

}  // namespace igms
