// The session info a log starts with (session_info_t): the scene's text and
// everything it reads (the model file, zlib-compressed; a trajectory file),
// and the hashes of the meshes the model names, so the log re-simulates on
// any machine, from the log alone; and beside it every robot's files
// (session_files_t) for a scene of several.
#pragma once

#include <string>

#include "core/simulation/simulation.h"
#include "igms/session_files_t.hpp"
#include "igms/session_info_t.hpp"

namespace igms {

session_info_t describeSession(const Simulation& sim, const std::string& clock);

// Every robot's files (session_files_t): session_info_t has room for the first robot's only.
session_files_t describeSessionFiles(const Simulation& sim);

}  // namespace igms
