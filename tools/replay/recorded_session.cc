#include "tools/replay/recorded_session.h"

#include <algorithm>
#include <filesystem>

#include "channels.h"
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
      if (safeDecode(e.data.data(), size, &m)) out.inputs.emplace(m.seq, m);
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
  // the server's working directory, base_dir.
  const std::filesystem::path path(session.info.scene_path);
  const std::filesystem::path dir = path.is_absolute() ? path.parent_path() : std::filesystem::path(base_dir) / path.parent_path();
  return parseScene(session.info.scene_text, session.info.scene_path, dir.empty() ? "." : dir.string());
}

}  // namespace igms
