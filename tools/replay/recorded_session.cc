#include "tools/replay/recorded_session.h"

#include <algorithm>
#include <cstdio>
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
    } else if (e.channel == channels::kSessionFiles && !out.has_files) {
      // The first that goes with the session info (the log's first event): its token and scene.
      session_files_t m;
      if (!safeDecode(e.data.data(), size, &m)) ++out.undecodable;
      else if (out.has_info && m.session_token == out.info.session_token && m.scene_path == out.info.scene_path) {
        out.files = std::move(m);
        out.has_files = true;
      }
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

bool predatesCouplingDamper(const std::string& build_version) {
  int major = 0, minor = 0;
  if (std::sscanf(build_version.c_str(), "igms %d.%d", &major, &minor) != 2) return true;  // older still: no version
  return major == 0 && minor < 2;
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
  if (session.has_files)
    for (const robot_files_t& r : session.files.robots)
      if (!r.trajectory_path.empty()) files[r.trajectory_path] = r.trajectory_text;
  Scene scene = parseScene(info.scene_text, info.scene_path, dir.empty() ? "." : dir.string(), &files);
  if (predatesCouplingDamper(info.build_version)) scene.push.b = 0.0;  // its pushes were eq. (3)'s spring alone
  if (session.has_files) {
    for (size_t k = 0; k < scene.robots.size() && k < session.files.robots.size(); ++k) {
      const robot_files_t& r = session.files.robots[k];
      if (r.model_size > 0)
        scene.robots[k].model_text = inflateText(r.model_zlib.data(), r.model_zlib.size(), static_cast<size_t>(r.model_size),
                                                 "the log's copy of " + r.model_path);
    }
  } else if (info.model_size > 0 && !scene.robots.empty()) {  // an older log: the first robot's model file
    scene.robots.front().model_text = inflateText(info.model_zlib.data(), info.model_zlib.size(), static_cast<size_t>(info.model_size),
                                   "the log's copy of " + info.model_path);
  }
  return scene;
}

namespace {

// Appends what differs between the recorded (uris, hashes) and the meshes here.
void compareMeshes(const std::vector<std::string>& uris, const std::vector<std::string>& hashes,
                   const std::vector<MeshFingerprint>& here_now, std::vector<std::string>* out) {
  std::map<std::string, std::string> now;
  for (const MeshFingerprint& m : here_now) now[m.uri] = m.hash;
  for (size_t i = 0; i < uris.size() && i < hashes.size(); ++i) {
    const auto it = now.find(uris[i]);
    const std::string here = it == now.end() ? "missing" : it->second;
    if (here != hashes[i]) out->push_back(uris[i] + ": recorded " + hashes[i] + ", here " + here);
  }
}

}  // namespace

std::vector<std::string> meshDifferences(const RecordedSession& session, const Model& model) {
  std::vector<std::string> out;
  const session_info_t& info = session.info;
  if (!session.has_files) {
    compareMeshes(info.mesh_uris, info.mesh_hashes, meshFingerprints(model, info.model_path), &out);
    return out;
  }
  // Each robot's meshes beside its own model file, the free bodies' beside the scene.
  size_t k = 0;
  std::vector<MeshFingerprint> free_bodies;
  for (const ModelPart& part : model.parts) {
    if (part.free_body) {
      for (MeshFingerprint& m : meshFingerprints(model, info.scene_path, part.frame_begin, part.frame_end))
        free_bodies.push_back(std::move(m));
      continue;
    }
    if (k >= session.files.robots.size()) continue;
    const robot_files_t& r = session.files.robots[k++];
    compareMeshes(r.mesh_uris, r.mesh_hashes, meshFingerprints(model, r.model_path, part.frame_begin, part.frame_end), &out);
  }
  compareMeshes(session.files.mesh_uris, session.files.mesh_hashes, free_bodies, &out);
  return out;
}

}  // namespace igms
