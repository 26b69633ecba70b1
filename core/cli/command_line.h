// How every igms program reads its command line (CLI11, Debian's
// libcli11-dev): --help, --version (the build's git describe), the same
// checks for URLs, durations and files, and errors that name the option:
//   igms-server: --duration: Value abc not in range [0 - 1.79769e+308]
//   Run with --help for more information.
// Exit codes: 0 after --help or --version, 2 for a bad command line.
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <string>

#include "igms_build_info.h"

namespace igms::cli {

// A program's app: its name, a one-line purpose, --version.
inline void describe(CLI::App& app, const std::string& purpose) {
  app.description(purpose);
  app.set_version_flag("--version", IGMS_BUILD_VERSION);
  app.option_defaults()->always_capture_default();
}

// An LCM URL: udpm://, memq:// or file://; a udpm:// URL keeps ttl=0 unless
// the user writes another ttl on purpose (two hosts).
inline const CLI::Validator LcmUrl(
    [](std::string& url) -> std::string {
      for (const char* scheme : {"udpm://", "memq://", "file://"})
        if (url.rfind(scheme, 0) == 0) return "";
      return "not an LCM URL (udpm://GROUP:PORT?ttl=0, memq://, file://LOG?speed=1)";
    },
    "URL");

// A finite number, >= 0 or > 0, named by what it measures in the help text.
inline CLI::Validator number(const std::string& what, bool positive) {
  return CLI::Validator(
      [positive](std::string& text) -> std::string {
        double x = 0.0;
        size_t used = 0;
        try {
          x = std::stod(text, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        if (used != text.size() || text.empty() || !std::isfinite(x) || x < 0.0 || (positive && x == 0.0))
          return std::string("expected a ") + (positive ? "positive" : "non-negative") + " number, got '" + text + "'";
        return "";
      },
      what);
}
inline const CLI::Validator Seconds = number("SECONDS", false);   // 0: no limit, where the option says so
inline CLI::Validator nonNegative(const std::string& unit) { return number(unit, false); }
inline CLI::Validator positive(const std::string& unit) { return number(unit, true); }

// Parses; returns -1 to go on, or the exit code to return from main.
inline int parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: %s\nRun with --help for more information.\n", app.get_name().c_str(), e.what());
    return 2;
  }
  return -1;
}

}  // namespace igms::cli
