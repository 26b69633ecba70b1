// igms-command: sends one command to the server (command_t on IGMS_COMMAND).
//
//   igms-command [--lcm-url URL] [--key-file FILE] [--timeout S] KIND [ARGS...]
//     KIND: pause | resume | step | reset | shutdown | load SCENE | save FILE | gains K_P K B [K_ROT B_ROT]
//
// It waits for the server's status and carries the session token it names,
// which binds the command to that session. On a signed bus (--key-file,
// IGMS_KEY_FILE) the command is also signed: the signature is the authority,
// and a signed command replayed into a later run of the server is refused. It
// then waits for the server's next status and reports whether the command
// was taken (the server's command counters), so a refused one is an exit
// code, not a silence.

#include <chrono>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bus/bus_key.h"
#include "bus/message_verifier.h"
#include "bus/signed_publisher.h"
#include "bus/subscription.h"
#include "channels.h"
#include "core/cli/command_line.h"
#include "core/realtime/clock.h"
#include "igms/command_t.hpp"
#include "igms/server_status_t.hpp"

namespace {

// The newest verified server status.
struct StatusWatch {
  StatusWatch(lcm::LCM& bus, std::optional<igms::bus::BusKey> key)
      : verifier(std::move(key), "igms-command"),
        in(igms::bus::subscribe<igms::server_status_t>(bus, verifier, igms::channels::kServerStatus,
                                                        [this](const igms::server_status_t& s, const igms::bus::Verdict&) {
                                                          status = s;
                                                          ++heard;
                                                        })) {}
  igms::bus::MessageVerifier verifier;
  igms::server_status_t status{};
  int64_t heard = 0;
  std::unique_ptr<igms::bus::Subscription<igms::server_status_t>> in;  // last: it writes the rest
};

// Handles the bus until `done` or the timeout; false on the timeout.
template <typename Done>
bool waitFor(lcm::LCM& bus, double timeout, Done done) {
  const double end = igms::monotonicSeconds() + timeout;
  while (!done()) {
    if (igms::monotonicSeconds() > end) return false;
    bus.handleTimeout(20);
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::string url, key_file, kind;
  std::vector<std::string> args;
  double timeout = 5.0;
  CLI::App app{"", "igms-command"};
  igms::cli::describe(app,
                      "Sends one command to igms-server and reports whether it was taken. Signed with the bus key "
                      "when there is one; else it carries the session token from the server's status. Run it "
                      "inside scripts/sessions/bus.sh run (or the namespace the server runs in).");
  app.add_option("--lcm-url", url, "LCM URL (default udpm://239.255.76.67:7667?ttl=0)")->check(igms::cli::LcmUrl);
  app.add_option("--key-file", key_file, igms::bus::kKeyFileHelp)->envname(igms::bus::kKeyFileEnv);
  app.add_option("--timeout", timeout, "seconds to wait for the server's status")->check(igms::cli::positive("S"));
  app.add_option("kind", kind, "pause, resume, step, reset, shutdown, load, save or gains")
      ->required()
      ->check(CLI::IsMember({"pause", "resume", "step", "reset", "shutdown", "load", "save", "gains"}));
  app.add_option("args", args, "load: SCENE; save: FILE; gains: K_P K B [K_ROT B_ROT]");
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;

  igms::command_t c{};
  c.utime = igms::wallMicros();
  c.seq = 1;
  static const std::map<std::string, int8_t> kinds = {
      {"pause", igms::command_t::PAUSE},       {"resume", igms::command_t::START},
      {"step", igms::command_t::STEP},         {"reset", igms::command_t::RESET},
      {"shutdown", igms::command_t::SHUTDOWN}, {"load", igms::command_t::LOAD_SCENE},
      {"save", igms::command_t::SAVE_TRAJECTORY}, {"gains", igms::command_t::SET_GAINS}};
  c.kind = kinds.at(kind);
  const size_t wanted = kind == "load" || kind == "save" ? 1 : 0;
  if (kind == "gains") {
    if (args.size() != 3 && args.size() != 5) {
      std::fprintf(stderr, "igms-command: gains takes K_P K B or K_P K B K_ROT B_ROT\n");
      return 2;
    }
    try {
      for (const std::string& a : args) c.values.push_back(std::stod(a));
    } catch (const std::exception&) {
      std::fprintf(stderr, "igms-command: gains: not numbers\n");
      return 2;
    }
    c.nvalues = static_cast<int32_t>(c.values.size());
  } else if (args.size() != wanted) {
    std::fprintf(stderr, "igms-command: %s takes %s\n", kind.c_str(),
                 wanted ? (kind == "load" ? "a scene file" : "a file name") : "no arguments");
    return 2;
  } else if (wanted) {
    c.text = args[0];
  }

  std::optional<igms::bus::BusKey> key;
  try {
    key = igms::bus::busKeyFor("igms-command", key_file);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-command: %s\n", e.what());
    return 2;
  }
  lcm::LCM bus(url.empty() ? igms::channels::kDefaultUrl : url);
  if (!bus.good()) {
    std::fprintf(stderr, "igms-command: cannot open LCM\n");
    return 2;
  }
  StatusWatch watch(bus, key);
  if (!waitFor(bus, timeout, [&] { return watch.heard > 0; })) {
    const bool refused = watch.verifier.counts().refusedTotal() > 0;
    std::fprintf(stderr, "igms-command: no server status within %.0f s%s\n", timeout,
                 refused ? " that passed the message check (a missing or wrong --key-file?)" : "");
    return 3;
  }
  const int64_t received = watch.status.commands_received, rejected = watch.status.commands_rejected;
  c.auth = std::to_string(watch.status.session_token);  // binds the command to this session (signed or not)
  igms::bus::SignedPublisher out(bus, key, 4096);
  out.publish(igms::channels::kCommand, c);
  // Taken: the server counted one more command and no more rejections. A shutdown ends the statuses.
  const bool counted = waitFor(bus, std::min(timeout, 2.0), [&] { return watch.status.commands_received > received; });
  if (!counted) {
    if (kind == "shutdown") {
      std::fprintf(stderr, "igms-command: shutdown sent\n");
      return 0;
    }
    std::fprintf(stderr, "igms-command: the server did not count the command (refused by its message check?)\n");
    return 1;
  }
  waitFor(bus, 0.3, [] { return false; });  // the status after the loop applied it
  if (watch.status.commands_rejected > rejected) {
    std::fprintf(stderr, "igms-command: %s refused: %s\n", kind.c_str(), watch.status.message.c_str());
    return 1;
  }
  std::fprintf(stderr, "igms-command: %s taken (server %s)\n", kind.c_str(), watch.status.state.c_str());
  return 0;
}
