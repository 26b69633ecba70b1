// Where the page's files and Debian's three.js are: the environment's
// IGMS_WEB_PAGE_DIR, else the installed copy next to an installed program
// (PREFIX/bin/x -> PREFIX/share/igms/web/page), else the source tree's
// web/page (IGMS_WEB_PAGE_DIR at build time).
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>

namespace igms::web {

inline std::string defaultPageDir() {
  if (const char* env = std::getenv("IGMS_WEB_PAGE_DIR")) return env;
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path installed = exe.parent_path().parent_path() / "share/igms/web/page";
    if (std::filesystem::exists(installed / "index.html", ec)) return installed.string();
  }
#ifdef IGMS_WEB_PAGE_DIR
  return IGMS_WEB_PAGE_DIR;
#else
  return "web/page";
#endif
}

inline const char* kDebianThreeDir = "/usr/share/javascript/three";  // package libjs-three (r111)

}  // namespace igms::web
