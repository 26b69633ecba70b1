// Commands (IGMS_COMMAND), applied by the loop between steps, never inside
// one. Each is validated: an unknown kind or invalid arguments are rejected
// with a reason (counted in the status), and a rejected command changes
// nothing, not even the paused/running state.
#pragma once

#include <string>

#include "core/simulation/simulation.h"
#include "igms/command_t.hpp"

namespace igms {

// What the loop does next, as the commands leave it.
struct LoopControl {
  bool paused = false;
  int steps_requested = 0;   // STEP: one step each, paused or not
  bool running = true;       // false: leave the loop (SHUTDOWN, LOAD_SCENE)
  bool reload = false;       // LOAD_SCENE: run scene_path next
  std::string scene_path;
  bool new_session = false;  // RESET happened: the caller issues a new token
};

struct CommandResult {
  bool accepted = true;
  std::string message;       // why it was rejected, or what failed
};

CommandResult applyCommand(const command_t& c, Simulation& sim, LoopControl& control);

}  // namespace igms
