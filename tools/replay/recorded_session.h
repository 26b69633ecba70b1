// A recorded session as the tools read it back from a log: the session info
// (and the session files: every robot's model, in logs since they came),
// the robot states in step order (the truth channel when the session was
// fault-injected, since it holds every step), the haptic inputs by seq, and
// the scene rebuilt from the logged scene text.
#pragma once

#include <map>
#include <utility>
#include <string>
#include <vector>

#include "igms/haptic_input_t.hpp"
#include "igms/robot_state_t.hpp"
#include "igms/session_files_t.hpp"
#include "igms/session_info_t.hpp"
#include "core/scene/scene.h"
#include "tools/eventlog/event_log.h"

namespace igms {

struct RecordedSession {
  bool has_info = false;
  session_info_t info;
  bool has_files = false;  // the files of the info's session (its token and scene): every robot's model; older logs have none
  session_files_t files;
  std::vector<robot_state_t> states;        // sorted by seq
  std::map<std::pair<int32_t, int64_t>, haptic_input_t> inputs;  // by (client_id, seq)
  // Messages on those channels that did not decode: damaged, or recorded with
  // other message types (another igms version: the type fingerprint differs).
  int64_t undecodable = 0;
};

RecordedSession readRecordedSession(const std::vector<log::Event>& events);

// The scene of the session; base_dir resolves a relative scene path (the
// server's working directory at record time), an absolute one needs none.
// Throws SceneError / ModelError.
// Each robot's model and trajectory file are the log's copies when it carries
// them (the session files: every robot; older logs: the session info's, the
// first robot's), else read from the disk.
// A session recorded by igms before 0.2 ("igms 0.1.0 (...)", or no version at all): its pushes had
// no coupling damper (interaction.coupling), and its scene re-simulates with b = 0, as recorded.
bool predatesCouplingDamper(const std::string& build_version);
Scene recordedScene(const RecordedSession& session, const std::string& base_dir);

// The meshes the model names whose files here differ from the recording's
// ("URI: recorded H, here H'"; "missing" when a file does not resolve):
// every robot's and free body's when the log has the session files.
std::vector<std::string> meshDifferences(const RecordedSession& session, const Model& model);

}  // namespace igms
