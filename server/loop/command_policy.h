// Who may command the server, and where its files may be. On a signed bus
// (--key-file) a command that arrived has passed its signature check, which
// is the proof; on an unauthenticated bus it must carry the current session
// token in `auth`. LOAD_SCENE reads scenes only below the
// configured scene folders, and SAVE_TRAJECTORY writes only below the output
// folder (a relative name without "..", or an absolute path inside it).
// Checked on the loop's thread before a command is applied; a refusal
// carries its reason for the server's status.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "igms/command_t.hpp"
#include "server/loop/command_handler.h"

namespace igms {

struct CommandPolicy {
  bool signed_bus = false;              // commands were checked on arrival; else the session token authorizes
  std::vector<std::string> scene_dirs;  // LOAD_SCENE only below these
  std::string output_dir = ".";         // SAVE_TRAJECTORY only below this
};

// Accepted: `*resolved` is the command to apply (file names made absolute
// inside their folder). Refused: the reason, and `*resolved` untouched.
CommandResult authorizeCommand(const command_t& c, int64_t session_token, const CommandPolicy& policy,
                               command_t* resolved);

// `path` (absolute, or relative to `base`) lies inside `folder` once both are
// made absolute and normalised, symbolic links in existing parts followed.
// Returns that absolute path, or "" when it would leave the folder.
std::string insideFolder(const std::string& path, const std::string& base, const std::string& folder);

}  // namespace igms
