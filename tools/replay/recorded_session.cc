#include "tools/replay/recorded_session.h"

#include <algorithm>
#include <filesystem>

#include "channels.h"
#include "core/model_io/model_fingerprint.h"
#include "core/model_io/zlib_text.h"
#include "safe_decode.h"

namespace igms {

RecordedSession readRecordedSession(const std::vector<log::Event>& events) {
  RecordedSession out;
  bool truth = false;
  for (const auto& e : events) truth |= e.channel == channels::kRobotStateTruth;
  const char* state_channel = truth ? channels::kRobotStateTruth : channels::kRobotState;
  for (const auto& e : events) {
    const int size = static_cast<int>(e.data.size());
    if (e.channel == channels::kSessionInfo && !out.has_info) {
      out.has_info = safeDecode(e.data.data(), size, &out.info);
      out.undecodable += !out.has_info;
    } else if (e.channel == channels::kHapticInput) {
      haptic_input_t m;
      if (safeDecode(e.data.data(), size, &m)) out.inputs.emplace(std::make_pair(m.client_id, m.seq), m);
      else ++out.undecodable;
    } else if (e.channel == state_channel) {
      robot_state_t m;
      if (safeDecode(e.data.data(), size, &m)) out.states.push_back(m);
      else ++out.undecodable;
    }
  }
  std::sort(out.states.begin(), out.states.end(), [](const auto& a, const auto& b) { return a.seq < b.seq; });
  return out;
}

Scene recordedScene(const RecordedSession& session, const std::string& base_dir) {
  // An absolute scene path (the server started with one) stands on its own; a relative one was relative to
  // the server's working directory, base_dir. The files the scene reads come from the log when it carries
  // them (the model, a trajectory file), so the paths matter only for meshes and for older logs.
  const session_info_t& info = session.info;
  const std::filesystem::path path(info.scene_path);
  const std::filesystem::path dir = path.is_absolute() ? path.parent_path() : std::filesystem::path(base_dir) / path.parent_path();
  std::map<std::string, std::string> files;
  if (!info.trajectory_path.empty()) files[info.trajectory_path] = info.trajectory_text;
  Scene scene = parseScene(info.scene_text, info.scene_path, dir.empty() ? "." : dir.string(), &files);
  if (info.model_size > 0 && !scene.robots.empty())  // the log carries the first robot's model file
    scene.robots.front().model_text = inflateText(info.model_zlib.data(), info.model_zlib.size(), static_cast<size_t>(info.model_size),
                                   "the log's copy of " + info.model_path);
  return scene;
}

std::vector<std::string> meshDifferences(const RecordedSession& session, const Model& model) {
  std::map<std::string, std::string> now;
  for (const MeshFingerprint& m : meshFingerprints(model, session.info.model_path)) now[m.uri] = m.hash;
  std::vector<std::string> out;
  const session_info_t& info = session.info;
  for (size_t i = 0; i < info.mesh_uris.size() && i < info.mesh_hashes.size(); ++i) {
    const auto it = now.find(info.mesh_uris[i]);
    const std::string here = it == now.end() ? "missing" : it->second;
    if (here != info.mesh_hashes[i])
      out.push_back(info.mesh_uris[i] + ": recorded " + info.mesh_hashes[i] + ", here " + here);
  }
  return out;
}

}  // namespace igms
