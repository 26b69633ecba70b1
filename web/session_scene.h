// What the page draws that does not move with the state: the robot's links
// and their geometry (visual, else collision, else a stick to the parent),
// the scene's obstacles, the nominal end-effector path, the interaction
// settings. Built once per session from session_info_t (scene file and text),
// off every loop, as the "hello" message a page gets when it connects.
#pragma once

#include <functional>
#include <string>

#include "igms/session_info_t.hpp"

namespace igms::web {

struct SessionScene {
  std::string key;          // scene path + model hash: a new session when it changes
  std::string hello_json;   // {"type":"hello", ...} without the role
  std::string error;        // why the scene could not be loaded ("" when it was)
  int nlinks = 0;
};

// serve(file) makes a mesh file reachable by the page and returns its URL
// path (WebServer::addFile).
SessionScene describeSession(const session_info_t& info, const std::function<std::string(const std::string&)>& serve);

}  // namespace igms::web
