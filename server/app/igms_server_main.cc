// igms-server --scene scenes/puma_wall.yaml [--lcm-url URL] [--clock realtime|lockstep]
//             [--duration S] [--save-edited FILE] [--session-token N] [--paused] [--quiet]
#include <sys/prctl.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "server/app/server.h"

namespace {
std::atomic<bool> g_stop{false};
void onSignal(int) { g_stop = true; }

int usage(const char* why) {
  if (why) std::fprintf(stderr, "igms-server: %s\n", why);
  std::fprintf(stderr,
               "usage: igms-server --scene FILE [--lcm-url URL] [--clock realtime|lockstep] [--duration S]\n"
               "                   [--save-edited FILE] [--session-token N] [--paused] [--quiet]\n"
               "                   [--fault-drop FRACTION] [--fault-burst-ms MS] [--fault-delay-us US]\n"
               "Run it inside scripts/netns_run.sh when the URL is udpm:// (the default).\n");
  return 2;
}
}  // namespace

int main(int argc, char** argv) {
  igms::ServerOptions o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        usage(("missing value after " + a).c_str());
        std::exit(2);
      }
      return argv[++i];
    };
    if (a == "--scene") o.scene_path = value();
    else if (a == "--lcm-url") o.lcm_url = value();
    else if (a == "--clock") {
      const std::string c = value();
      if (c == "realtime") o.clock = igms::ServerOptions::Clock::Realtime;
      else if (c == "lockstep") o.clock = igms::ServerOptions::Clock::Lockstep;
      else return usage("--clock is realtime or lockstep");
    } else if (a == "--duration") o.duration = std::atof(value().c_str());
    else if (a == "--save-edited") o.save_edited = value();
    else if (a == "--session-token") o.session_token = std::atoll(value().c_str());
    else if (a == "--paused") o.start_paused = true;
    else if (a == "--quiet") o.quiet = true;
    else if (a == "--fault-drop") o.fault_drop = std::atof(value().c_str());
    else if (a == "--fault-burst-ms") o.fault_burst_ms = std::atof(value().c_str());
    else if (a == "--fault-delay-us") o.fault_delay_us = std::atof(value().c_str());
    else if (a == "-h" || a == "--help") { usage(nullptr); return 0; }
    else return usage(("unknown argument " + a).c_str());
  }
  if (o.scene_path.empty()) return usage("--scene is required");
  // Sleeps wake within 1 us of their time, not the default 50 us of slack.
  prctl(PR_SET_TIMERSLACK, 1000UL, 0, 0, 0);
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  return igms::runServer(o, g_stop);
}
