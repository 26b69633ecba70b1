// igms-relay: a network between the client and the server, for rehearsal.
// The client uses one LCM URL, the server another; the relay forwards the
// client's channels up and the server's down, each direction through its own
// DelayLine (delay, jitter, loss, reordering), and counts what it did. The
// kernel here has no netem; this is the user-space equivalent for LCM.
// Signed messages pass through unchanged (the signature holds end to end);
// with the bus key the relay also checks each one and forwards only what
// passes, counting the rest.
//   igms-relay --client-url URL --server-url URL [--delay-ms D] [--jitter-ms J] [--loss P]
//              [--up-delay-ms ...] [--down-loss ...] [--in-order] [--seed N] [--duration S]
//              [--rt-priority N]

#include <poll.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <limits>
#include <memory>
#include <regex>
#include <string>

#include "bus/bus_key.h"
#include "bus/message_verifier.h"
#include "bus/subscription.h"
#include "core/cli/command_line.h"
#include "core/realtime/realtime_priority.h"
#include "core/realtime/stop_signal.h"
#include "tools/relay/delay_line.h"

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Options {
  std::string client_url, server_url;
  std::string up_channels = "IGMS_(HAPTIC_INPUT|COMMAND|CLIENT_STATUS|HEARTBEAT)";
  std::string down_channels = "IGMS_(ROBOT_STATE|ROBOT_STATE_TRUTH|SERVER_STATUS|SESSION_INFO|TRAJECTORY_EDITED)";
  double delay_ms = 0, jitter_ms = 0, loss = 0;
  double up_delay_ms = -1, up_jitter_ms = -1, up_loss = -1;
  double down_delay_ms = -1, down_jitter_ms = -1, down_loss = -1;
  bool in_order = false;
  unsigned seed = 1;
  double duration = 0, status_s = 0;
  int rt_priority = 0;
  std::string key_file;
};

igms::PathFaults faults(const Options& o, double delay, double jitter, double loss) {
  igms::PathFaults f;
  f.delay_ms = delay >= 0 ? delay : o.delay_ms;
  f.jitter_ms = jitter >= 0 ? jitter : o.jitter_ms;
  f.loss = loss >= 0 ? loss : o.loss;
  f.in_order = o.in_order;
  return f;
}

// One direction: subscribed on `from`, published on `to`.
class Path {
 public:
  Path(const char* name, lcm::LCM& from, lcm::LCM& to, const std::string& channels, const igms::PathFaults& f,
       uint32_t seed, const std::optional<igms::bus::BusKey>& key)
      : name_(name), to_(to), line_(f, seed), verifier_(key, "igms-relay") {
    verifier_.acceptReplays();  // a link: replays pass as they are, the far end decides
    // What is accepted goes on as it arrived, trailer and all; what is refused is counted, not forwarded.
    in_ = igms::bus::subscribeRaw(
        from, verifier_, channels,
        [this](const std::string& channel, const lcm::ReceiveBuffer& m, const igms::bus::Verdict&) {
          line_.admit(channel, static_cast<const uint8_t*>(m.data), m.data_size, now());
        },
        {100000, nullptr, nullptr});
  }
  void release(double t) {
    while (line_.popDue(t, &held_)) to_.publish(held_.channel, held_.data.data(), static_cast<unsigned>(held_.data.size()));
  }
  double nextRelease() const { return line_.nextRelease(); }
  void print() const {
    const igms::PathCounts& c = line_.counts();
    const igms::PathFaults& f = line_.faults();
    std::fprintf(stderr,
                 "igms-relay: %s (delay %.3g ms, jitter %.3g ms, loss %.3g): received %lld, forwarded %lld, dropped "
                 "%lld, overflowed %lld, reordered %lld, held at most %zu\n",
                 name_, f.delay_ms, f.jitter_ms, f.loss, static_cast<long long>(c.received),
                 static_cast<long long>(c.forwarded), static_cast<long long>(c.dropped),
                 static_cast<long long>(c.overflowed), static_cast<long long>(c.reordered), c.max_queued);
    if (verifier_.keyed()) std::fprintf(stderr, "igms-relay:   %s: bus: %s\n", name_, verifier_.summary().c_str());
  }

 private:
  const char* name_;
  lcm::LCM& to_;
  igms::DelayLine line_;
  igms::HeldMessage held_;
  igms::bus::MessageVerifier verifier_;
  std::unique_ptr<igms::bus::RawSubscription> in_;
};

int run(const Options& o, const std::atomic<bool>& stop) {
  std::optional<igms::bus::BusKey> key;
  try {
    if (!o.key_file.empty()) key = igms::bus::loadBusKey(o.key_file);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-relay: %s\n", e.what());
    return 2;
  }
  lcm::LCM client(o.client_url), server(o.server_url);
  if (!client.good() || !server.good()) {
    std::fprintf(stderr, "igms-relay: cannot open LCM at %s\n", (client.good() ? o.server_url : o.client_url).c_str());
    return 2;
  }
  Path up("up (client to server)", client, server, o.up_channels, faults(o, o.up_delay_ms, o.up_jitter_ms, o.up_loss),
          o.seed, key);
  Path down("down (server to client)", server, client, o.down_channels,
            faults(o, o.down_delay_ms, o.down_jitter_ms, o.down_loss), o.seed + 1, key);
  std::fprintf(stderr, "igms-relay: client side %s, server side %s\n", o.client_url.c_str(), o.server_url.c_str());
  // A relay that the scheduler holds back delays every message by the stall: a path with a
  // steady delay needs the relay as punctual as the loops at its ends.
  if (o.rt_priority > 0) igms::requestRealtimeAndSay("igms-relay", "relay", o.rt_priority);
  const double start = now();
  double next_status = start + o.status_s;
  pollfd fds[2] = {{client.getFileno(), POLLIN, 0}, {server.getFileno(), POLLIN, 0}};
  while (!stop && (o.duration <= 0 || now() - start < o.duration)) {
    const double wait = std::min({up.nextRelease(), down.nextRelease(), now() + 0.05}) - now();
    const timespec ts{0, static_cast<long>(std::max(0.0, wait) * 1e9)};
    if (ppoll(fds, 2, &ts, nullptr) > 0) {
      if (fds[0].revents & POLLIN) client.handle();
      if (fds[1].revents & POLLIN) server.handle();
    }
    const double t = now();
    up.release(t);
    down.release(t);
    if (o.status_s > 0 && t >= next_status) {
      up.print();
      down.print();
      next_status = t + o.status_s;
    }
  }
  up.print();
  down.print();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"", "igms-relay"};
  igms::cli::describe(app,
                      "Forwards the client's channels from one LCM URL to the server's and the server's back, "
                      "delaying, jittering, dropping and reordering each direction, and counts what it did.");
  app.add_option("--client-url", o.client_url, "the URL the client uses")->required()->check(igms::cli::LcmUrl);
  app.add_option("--server-url", o.server_url, "the URL the server uses (another port or group)")
      ->required()
      ->check(igms::cli::LcmUrl);
  app.add_option("--key-file", o.key_file,
                 "forward only messages signed with the bus key in this file, counting the rest (default: "
                 "$IGMS_KEY_FILE; without one, everything is forwarded and the signatures hold end to end)")
      ->envname(igms::bus::kKeyFileEnv);
  app.add_option("--delay-ms", o.delay_ms, "one-way delay, both directions")->check(igms::cli::nonNegative("MS"));
  app.add_option("--jitter-ms", o.jitter_ms, "uniform jitter +- this, both directions")
      ->check(igms::cli::nonNegative("MS"));
  app.add_option("--loss", o.loss, "probability a message is dropped, both directions")->check(CLI::Range(0.0, 1.0));
  app.add_option("--up-delay-ms", o.up_delay_ms, "client to server only")->check(igms::cli::nonNegative("MS"));
  app.add_option("--up-jitter-ms", o.up_jitter_ms, "client to server only")->check(igms::cli::nonNegative("MS"));
  app.add_option("--up-loss", o.up_loss, "client to server only")->check(CLI::Range(0.0, 1.0));
  app.add_option("--down-delay-ms", o.down_delay_ms, "server to client only")->check(igms::cli::nonNegative("MS"));
  app.add_option("--down-jitter-ms", o.down_jitter_ms, "server to client only")->check(igms::cli::nonNegative("MS"));
  app.add_option("--down-loss", o.down_loss, "server to client only")->check(CLI::Range(0.0, 1.0));
  app.add_flag("--in-order", o.in_order, "jitter without reordering (a message waits for the one before it)");
  app.add_option("--up-channels", o.up_channels, "channels forwarded client to server (a regular expression)");
  app.add_option("--down-channels", o.down_channels, "channels forwarded server to client (a regular expression)");
  app.add_option("--seed", o.seed, "seed of the loss and jitter draws");
  app.add_option("--duration", o.duration, "seconds to run (0: until stopped)")->check(igms::cli::Seconds);
  app.add_option("--status-s", o.status_s, "print the counts this often (0: at the end only)")
      ->check(igms::cli::Seconds);
  app.add_option("--rt-priority", o.rt_priority,
                 "ask for SCHED_FIFO at this priority (1-99) and lock memory, as igms-server and igms-haptic do; a "
                 "warning and a normal process when not allowed (0: do not ask)")
      ->check(CLI::Range(0, 99));
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  if (o.client_url == o.server_url) {
    std::fprintf(stderr, "igms-relay: --client-url and --server-url must differ (the relay would echo itself)\n");
    return 2;
  }
  for (const std::string* re : {&o.up_channels, &o.down_channels}) {
    try {
      std::regex r(*re);
    } catch (const std::regex_error& e) {
      std::fprintf(stderr, "igms-relay: bad channel expression '%s': %s\n", re->c_str(), e.what());
      return 2;
    }
  }
  return run(o, igms::stopOnSignals());
}
