// The session info a log starts with (session_info_t): the scene's text and
// everything it reads (the model file, zlib-compressed; a trajectory file),
// and the hashes of the meshes the model names, so the log re-simulates on
// any machine, from the log alone.
#pragma once

#include <string>

#include "core/simulation/simulation.h"
#include "igms/session_info_t.hpp"

namespace igms {

session_info_t describeSession(const Simulation& sim, const std::string& clock);

}  // namespace igms
