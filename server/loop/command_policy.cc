#include "server/loop/command_policy.h"

#include <filesystem>

namespace igms {
namespace {

namespace fs = std::filesystem;

bool sameSecret(const std::string& given, const std::string& expected) {
  // Constant time in the secret's length: no early exit on the first mismatch.
  unsigned diff = given.size() == expected.size() ? 0u : 1u;
  for (size_t i = 0; i < expected.size(); ++i) diff |= static_cast<unsigned char>(expected[i]) ^
                                                       static_cast<unsigned char>(i < given.size() ? given[i] : 0);
  return diff == 0 && !expected.empty();
}

CommandResult refused(const std::string& why) { return {false, why}; }

}  // namespace

std::string insideFolder(const std::string& path, const std::string& base, const std::string& folder) {
  if (path.empty() || path.find('\0') != std::string::npos) return "";
  std::error_code ec;
  const fs::path root = fs::weakly_canonical(fs::absolute(folder, ec), ec);
  if (ec) return "";
  fs::path p(path);
  if (p.is_relative()) p = fs::path(base) / p;
  const fs::path full = fs::weakly_canonical(fs::absolute(p, ec), ec);
  if (ec) return "";
  // Inside: root is a prefix of full, component by component.
  auto r = root.begin(), f = full.begin();
  for (; r != root.end(); ++r, ++f) {
    if (r->empty()) continue;  // a trailing separator
    if (f == full.end() || *r != *f) return "";
  }
  return full.string();
}

CommandResult authorizeCommand(const command_t& c, int64_t signed_us, int64_t session_token,
                               const CommandPolicy& policy, command_t* resolved) {
  if (policy.signed_bus && signed_us < policy.started_us)
    return refused("signed before this server started: a command of an earlier session, replayed");
  if (!sameSecret(c.auth, std::to_string(session_token)))
    return refused(policy.signed_bus ? "not this session's: a command must carry the current session token (from "
                                       "the server's status); a command of an earlier session is refused"
                                     : "not authorized: a command must carry the session token");
  command_t out = c;
  if (c.kind == command_t::LOAD_SCENE) {
    // A relative name: from the server's working directory, or from a scene folder.
    std::string found;
    for (const std::string& dir : policy.scene_dirs) {
      for (const std::string& base : {std::string("."), dir}) {
        const std::string candidate = insideFolder(c.text, base, dir);
        if (!candidate.empty() && fs::is_regular_file(candidate)) found = candidate;
        if (!found.empty()) break;
      }
      if (!found.empty()) break;
    }
    if (found.empty()) return refused("LOAD_SCENE: '" + c.text.substr(0, 200) + "' is not a scene file in a scene folder (--scene-dir)");
    out.text = found;
  } else if (c.kind == command_t::SAVE_TRAJECTORY) {
    const std::string found = insideFolder(c.text, policy.output_dir, policy.output_dir);
    if (found.empty())
      return refused("SAVE_TRAJECTORY: '" + c.text.substr(0, 200) + "' is not in the output folder (--output-dir)");
    out.text = found;
  }
  *resolved = std::move(out);
  return {};
}

}  // namespace igms
