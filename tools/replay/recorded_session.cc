#include "tools/replay/recorded_session.h"

#include <algorithm>

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
  const std::string& path = session.info.scene_path;
  const size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? base_dir : base_dir + "/" + path.substr(0, slash);
  return parseScene(session.info.scene_text, path, dir);
}

}  // namespace igms
