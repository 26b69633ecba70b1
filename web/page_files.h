// Where the page's files and Debian's three.js are: IGMS_WEB_PAGE_DIR (the
// source tree's web/page, or the installed copy) unless the environment's
// IGMS_WEB_PAGE_DIR says otherwise.
#pragma once

#include <cstdlib>
#include <string>

namespace igms::web {

inline std::string defaultPageDir() {
  if (const char* env = std::getenv("IGMS_WEB_PAGE_DIR")) return env;
#ifdef IGMS_WEB_PAGE_DIR
  return IGMS_WEB_PAGE_DIR;
#else
  return "web/page";
#endif
}

inline const char* kDebianThreeDir = "/usr/share/javascript/three";  // package libjs-three (r111)

}  // namespace igms::web
