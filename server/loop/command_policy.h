// Who may command the server, and where its files may be. Every command must
// carry the current session token in `auth` (a new one at each start and
// reset), which binds it to this server's session. On an unauthenticated bus
// the token is the proof; on a signed bus (--key-file) the signature checked
// on arrival is, and the token and the signature's time (after this server
// started) keep a command captured from an earlier run of the server from
// being replayed into this one. LOAD_SCENE reads scenes only below the
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
  bool signed_bus = false;              // commands were checked on arrival (their signature's time is known)
  int64_t started_us = 0;               // the server's start (wall clock, us): a signed command is signed after it
  std::vector<std::string> scene_dirs;  // LOAD_SCENE only below these
  std::string output_dir = ".";         // SAVE_TRAJECTORY only below this
};

// Accepted: `*resolved` is the command to apply (file names made absolute
// inside their folder). Refused: the reason, and `*resolved` untouched.
// `signed_us`: when its signature was made (the sender's wall clock, us; 0 on an unauthenticated bus).
CommandResult authorizeCommand(const command_t& c, int64_t signed_us, int64_t session_token,
                               const CommandPolicy& policy, command_t* resolved);

// `path` (absolute, or relative to `base`) lies inside `folder` once both are
// made absolute and normalised, symbolic links in existing parts followed.
// Returns that absolute path, or "" when it would leave the folder.
std::string insideFolder(const std::string& path, const std::string& base, const std::string& folder);

}  // namespace igms
