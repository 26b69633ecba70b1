// igms-haptic --scene scenes/puma_obstacle.yaml --device scripted:scenes/push_demo.yaml
//             [--lcm-url URL] [--rate HZ] [--deadline-us US] [--fallback hold|extrapolate|interpolate]
//             [--lost-ms MS] [--client-id N] [--duration S] [--quiet]
#include <sys/prctl.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "haptic_client/app/haptic_client.h"

namespace {
std::atomic<bool> g_stop{false};
void onSignal(int) { g_stop = true; }
int usage(const char* why) {
  if (why) std::fprintf(stderr, "igms-haptic: %s\n", why);
  std::fprintf(stderr,
               "usage: igms-haptic --scene FILE --device scripted:FILE|replay:LOG [--lcm-url URL] [--rate HZ]\n"
               "                   [--deadline-us US] [--fallback hold|extrapolate|interpolate] [--lost-ms MS]\n"
               "                   [--client-id N] [--duration S] [--quiet]\n");
  return 2;
}
}  // namespace

int main(int argc, char** argv) {
  igms::ClientOptions o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc && a != "--quiet" && a != "-h" && a != "--help") return usage(("missing value after " + a).c_str());
    if (a == "--scene") o.scene_path = argv[++i];
    else if (a == "--device") o.device = argv[++i];
    else if (a == "--lcm-url") o.lcm_url = argv[++i];
    else if (a == "--rate") o.rate_hz = std::atof(argv[++i]);
    else if (a == "--deadline-us") o.deadline_us = std::atof(argv[++i]);
    else if (a == "--fallback") o.fallback = argv[++i];
    else if (a == "--lost-ms") o.lost_ms = std::atof(argv[++i]);
    else if (a == "--client-id") o.client_id = std::atoi(argv[++i]);
    else if (a == "--duration") o.duration = std::atof(argv[++i]);
    else if (a == "--quiet") o.quiet = true;
    else if (a == "-h" || a == "--help") { usage(nullptr); return 0; }
    else return usage(("unknown argument " + a).c_str());
  }
  if (o.scene_path.empty() || o.device.empty()) return usage("--scene and --device are required");
  if (!(o.rate_hz > 0) || !(o.deadline_us > 0)) return usage("--rate and --deadline-us must be positive");
  // Sleeps wake within 1 us of their time, not the default 50 us of slack.
  prctl(PR_SET_TIMERSLACK, 1000UL, 0, 0, 0);
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  return igms::runClient(o, g_stop);
}
