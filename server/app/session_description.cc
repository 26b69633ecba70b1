#include "server/app/session_description.h"

#include "core/model_io/model_fingerprint.h"
#include "core/model_io/zlib_text.h"
#include "igms_build_info.h"

namespace igms {

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
  std::string model_text = robot.model_text;
  if (model_text.empty() && !robot.model_path.empty()) {
    try {
      model_text = readModelFile(robot.model_path);
    } catch (const std::exception&) {
    }
  }
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

}  // namespace igms
