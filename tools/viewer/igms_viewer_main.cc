// igms-viewer [--lcm-url URL] [--port P] [--bind ADDR] [--log FILE]
// The live 3-D view of a session in the browser (or a recorded one, with a
// timeline). Prints the page's URL as its first line of stdout.

#include <chrono>
#include <cstdio>
#include <memory>
#include <thread>

#include "bus/bus_key.h"
#include "channels.h"
#include "core/cli/command_line.h"
#include "core/realtime/stop_signal.h"
#include "tools/viewer/log_player.h"
#include "web/bus_feed.h"
#include "web/page_files.h"
#include "web/view_service.h"

namespace {

using igms::web::PageMessage;

// Replay controls: {"type":"replay","action":"play"|"pause"|"seek"|"speed","t":S,"speed":X}.
PageMessage replayControl(igms::LogPlayer* player, const nlohmann::json& m) {
  if (m["type"] == "device" || m["type"] == "command") return PageMessage::NeedsToken;  // no device here
  if (m["type"] != "replay" || !player) return PageMessage::Malformed;
  if (!m.contains("action") || !m["action"].is_string()) return PageMessage::Malformed;
  const std::string action = m["action"];
  auto number = [&](const char* key, double* out) {
    if (!m.contains(key) || !m[key].is_number()) return false;
    *out = m[key].get<double>();
    return std::isfinite(*out);
  };
  double x = 0.0;
  if (action == "play") player->play();
  else if (action == "pause") player->pause();
  else if (action == "seek" && number("t", &x)) player->seek(x);
  else if (action == "speed" && number("speed", &x) && x > 0) player->speed(x);
  else return PageMessage::Malformed;
  return PageMessage::Handled;
}

}  // namespace

int main(int argc, char** argv) {
  std::string url = igms::channels::kDefaultUrl, log_path;
  igms::web::WebServerOptions web;
  web.port = 8080;
  web.page_dir = igms::web::defaultPageDir();
  web.three_dir = igms::web::kDebianThreeDir;
  double frame_hz = 60.0;
  CLI::App app{"", "igms-viewer"};
  igms::cli::describe(app,
                      "The live 3-D view of an igms session in a web browser: the robot, the scene, the device tip, "
                      "forces, paths and the server's and client's figures. It needs only the bus: the scene comes "
                      "from the server's session info. With --log it plays a recorded session with a timeline. "
                      "Prints the page's URL as its first line. Run it inside scripts/netns_run.sh with a udpm:// URL.");
  app.add_option("--lcm-url", url, "LCM URL (default udpm://239.255.76.67:7667?ttl=0)")->check(igms::cli::LcmUrl);
  std::string key_file;
  app.add_option("--key-file", key_file, igms::bus::kKeyFileHelp)->envname(igms::bus::kKeyFileEnv);
  app.add_option("--port", web.port, "HTTP port (0: any free port)")->check(CLI::Range(0, 65535));
  app.add_option("--bind", web.bind, "address to listen on (default 127.0.0.1: this machine only)");
  app.add_flag("--allow-no-origin", web.allow_no_origin,
               "take WebSockets without an Origin header (a script of your own; browsers always send one)");
  app.add_option("--log", log_path, "play this recorded session (.lcmlog or .lcmlog.gz) instead of the bus")
      ->check(CLI::ExistingFile);
  app.add_option("--frame-rate", frame_hz, "frames per second to the browser (default 60)")
      ->check(CLI::Range(1.0, 240.0));
  app.add_option("--page-dir", web.page_dir, "the page's files (default: the build's web/page)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--three-dir", web.three_dir, "three.js (default Debian's libjs-three)")
      ->check(CLI::ExistingDirectory);
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;

  igms::web::ViewService view(web, frame_hz);
  std::unique_ptr<igms::LogPlayer> player;
  std::unique_ptr<igms::web::BusFeed> feed;
  try {
    if (!log_path.empty()) {
      player = std::make_unique<igms::LogPlayer>(log_path, view.bus());
      igms::LogPlayer* p = player.get();
      view.clock([p] { return p->time(); });
      view.frameExtra([p] { return p->timelineJson(); });
    } else {
      feed = std::make_unique<igms::web::BusFeed>(url, view.bus(), igms::bus::busKeyFor("igms-viewer", key_file));
    }
    view.onPageMessage([p = player.get()](int, bool, const nlohmann::json& m) { return replayControl(p, m); });
    view.start();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-viewer: %s\n", e.what());
    return 2;
  }
  std::printf("%s\n", view.url(false).c_str());
  std::fflush(stdout);
  std::fprintf(stderr, "igms-viewer: %s; open the URL above in a browser\n",
               player ? ("playing " + log_path).c_str() : ("watching " + url).c_str());
  const std::atomic<bool>& stop = igms::stopOnSignals();
  // Loud silence: a live viewer that hears no robot state for 3 s says so (once per silence) on stderr,
  // as the page's banner does.
  auto last_heard = std::chrono::steady_clock::now();
  int64_t states = 0;
  bool silence_said = false;
  while (!stop) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    if (player) continue;
    const auto now = std::chrono::steady_clock::now();
    if (const int64_t n = view.bus().states(); n != states) {
      states = n;
      last_heard = now;
      silence_said = false;
    } else if (!silence_said && now - last_heard >= std::chrono::seconds(3)) {
      std::fprintf(stderr,
                   "igms-viewer: no robot state on %s for 3 s%s (is the server on this bus? processes started by "
                   "separate scripts/netns_run.sh calls do not hear each other: use scripts/sessions/bus.sh run)\n",
                   url.c_str(), states ? " since the last one" : "");
      silence_said = true;
    }
  }
  view.stop();
  const auto& c = view.server().counters();
  std::fprintf(stderr,
               "igms-viewer: %lld frames sent, %lld skipped, %lld page messages (%lld malformed, %lld without the "
               "token), %lld bus messages undecodable\n",
               static_cast<long long>(c.frames_sent), static_cast<long long>(c.frames_skipped),
               static_cast<long long>(c.messages), static_cast<long long>(c.rejected_malformed),
               static_cast<long long>(c.rejected_token), static_cast<long long>(view.bus().undecodable()));
  return 0;
}
