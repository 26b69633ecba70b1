// bus_forger: a process without the bus key that tries everything against a
// signed session (tests/integration/forger_test.sh). It listens to the real
// server's states and status and the real client's inputs, and publishes:
//   - each state changed (seq + 10^8, joints 2 and 3 turned by +-0.6 rad, velocities zeroed)
//     unsigned, with the captured signature kept, and signed with a random key;
//   - each state and input replayed as captured (a valid signature, an old counter), at once and 50 later;
//   - inputs of its own with the session token, pushing 5 cm deep into link 2, unsigned and with a random key;
//   - commands (SHUTDOWN, PAUSE, RESET, SAVE_TRAJECTORY forged.yaml), unsigned and with a random key, 5 a second;
//   - signed-looking junk (random bytes with a trailer's magic) on every channel, --junk-hz a second.
// It takes as genuine only signed messages of a sender not its own with a counter newer than that
// sender's last (so it never forges from its own output). Prints what it sent as JSON.
//   bus_forger --lcm-url URL --duration S [--junk-hz N] [--stats FILE]
#include <chrono>
#include <cstdio>
#include <cstring>
#include <deque>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "bus/message_signature.h"
#include "bus/message_signer.h"
#include "channels.h"
#include "core/realtime/stop_signal.h"
#include "igms/command_t.hpp"
#include "igms/haptic_input_t.hpp"
#include "igms/robot_state_t.hpp"
#include "igms/server_status_t.hpp"
#include "safe_decode.h"

namespace {

using Bytes = std::vector<uint8_t>;

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

igms::bus::BusKey randomKey(std::mt19937_64& rng) {
  igms::bus::BusKey k{};
  for (auto& b : k) b = static_cast<uint8_t>(rng());
  return k;
}

class Forger {
 public:
  Forger(lcm::LCM& bus, int junk_hz) : bus_(bus), rng_(std::random_device{}()), stranger_(randomKey(rng_)), junk_hz_(junk_hz) {}

  void onMessage(const lcm::ReceiveBuffer* rbuf, const std::string& channel) {
    const auto* d = static_cast<const uint8_t*>(rbuf->data);
    igms::bus::Trailer t;
    if (!igms::bus::findTrailer(d, rbuf->data_size, &t) || t.sender == igms::bus::processSender()) return;
    uint64_t& last = last_counter_[channel + std::string(t.sender.begin(), t.sender.end())];
    if (t.counter <= last) return;  // a replay (ours or anyone's): not a genuine new message
    last = t.counter;
    const Bytes captured(d, d + rbuf->data_size);
    if (channel == igms::channels::kRobotState) forgeState(captured, t);
    else if (channel == igms::channels::kHapticInput) replay(channel, captured);
    else if (channel == igms::channels::kServerStatus) {
      igms::server_status_t s;
      if (igms::safeDecode(d, t.payload_bytes, &s)) token_ = s.session_token;
    }
  }

  void tick() {
    const double t = now();
    if (t >= next_command_) {
      next_command_ = t + 0.2;
      forgeCommand();
      forgeInput();
    }
    while (junk_hz_ > 0 && t >= next_junk_) {
      next_junk_ += 1.0 / junk_hz_;
      junk();
    }
  }

  void print(std::FILE* out) const {
    std::fprintf(out, "{");
    bool first = true;
    for (const auto& [kind, n] : sent_) {
      std::fprintf(out, "%s\"%s\": %lld", first ? "" : ", ", kind.c_str(), static_cast<long long>(n));
      first = false;
    }
    std::fprintf(out, "}\n");
  }

 private:
  void send(const std::string& kind, const std::string& channel, const Bytes& b) {
    bus_.publish(channel, b.data(), static_cast<unsigned>(b.size()));
    ++sent_[kind];
  }
  // Unsigned, with `trailer` appended as captured (now wrong), and signed with a random key.
  void sendThreeWays(const std::string& what, const std::string& channel, Bytes payload, const uint8_t* trailer) {
    send(what + "_unsigned", channel, payload);
    if (trailer) {
      Bytes kept = payload;
      kept.insert(kept.end(), trailer, trailer + igms::bus::kTrailerBytes);
      send(what + "_stale_signature", channel, kept);
    }
    const size_t n = payload.size();
    payload.resize(n + igms::bus::kTrailerBytes);
    payload.resize(stranger_.sign(channel, payload.data(), n));
    send(what + "_random_key", channel, payload);
  }
  template <typename M>
  static Bytes encode(const M& m) {
    Bytes b(static_cast<size_t>(m.getEncodedSize()));
    m.encode(b.data(), 0, static_cast<int>(b.size()));
    return b;
  }

  void forgeState(const Bytes& captured, const igms::bus::Trailer& t) {
    igms::robot_state_t s;
    if (!igms::safeDecode(captured.data(), t.payload_bytes, &s)) return;
    s.seq += 100000000;
    if (s.nq > 2) {
      s.q[1] += 0.6;
      s.q[2] -= 0.6;
    }
    std::fill(s.v.begin(), s.v.end(), 0.0);
    sendThreeWays("state", igms::channels::kRobotState, encode(s), captured.data() + t.payload_bytes);
    replay(igms::channels::kRobotState, captured);
  }

  // At once, and again 50 messages later.
  void replay(const std::string& channel, const Bytes& captured) {
    send("replay_" + channel, channel, captured);
    auto& ring = held_[channel];
    ring.push_back(captured);
    if (ring.size() > 50) {
      send("replay_late_" + channel, channel, ring.front());
      ring.pop_front();
    }
  }

  void forgeInput() {
    if (!token_) return;
    igms::haptic_input_t in{};
    in.utime = 0;
    in.seq = ++input_seq_ + 100000000;
    in.client_id = 7;
    in.session_token = token_;
    in.mode = igms::haptic_input_t::MODE_PUSH;
    in.tip_position[0] = 0.3;
    in.tip_position[2] = 0.5;
    in.tip_radius = 0.05;
    in.contact_link = "link2";
    in.attach_orientation[0] = 1;
    in.tip_orientation[0] = 1;
    sendThreeWays("input", igms::channels::kHapticInput, encode(in), nullptr);
  }

  void forgeCommand() {
    static const int8_t kinds[] = {igms::command_t::SHUTDOWN, igms::command_t::PAUSE, igms::command_t::RESET,
                                   igms::command_t::SAVE_TRAJECTORY};
    igms::command_t c{};
    c.kind = kinds[command_k_++ % 4];
    c.seq = command_k_;
    c.text = "forged.yaml";
    c.auth = std::to_string(token_);  // the token the server publishes: no longer enough
    sendThreeWays("command", igms::channels::kCommand, encode(c), nullptr);
  }

  void junk() {
    static const char* channels[] = {igms::channels::kRobotState, igms::channels::kHapticInput,
                                     igms::channels::kCommand, igms::channels::kServerStatus,
                                     igms::channels::kSessionInfo};
    Bytes b(64 + rng_() % 400);
    for (auto& x : b) x = static_cast<uint8_t>(rng_());
    std::memcpy(b.data() + b.size() - igms::bus::kTrailerBytes, igms::bus::kMagic, sizeof igms::bus::kMagic);
    send("junk", channels[junk_k_++ % 5], b);
  }

  lcm::LCM& bus_;
  std::mt19937_64 rng_;
  igms::bus::MessageSigner stranger_;
  int junk_hz_;
  std::map<std::string, uint64_t> last_counter_;
  std::map<std::string, std::deque<Bytes>> held_;
  std::map<std::string, int64_t> sent_;
  int64_t token_ = 0, input_seq_ = 0;
  int command_k_ = 0, junk_k_ = 0;
  double next_command_ = 0, next_junk_ = now();
};

}  // namespace

int main(int argc, char** argv) {
  std::string url = igms::channels::kDefaultUrl, stats;
  double duration = 10;
  int junk_hz = 2000;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--lcm-url") url = argv[i + 1];
    else if (a == "--duration") duration = std::stod(argv[i + 1]);
    else if (a == "--junk-hz") junk_hz = std::stoi(argv[i + 1]);
    else if (a == "--stats") stats = argv[i + 1];
  }
  lcm::LCM bus(url);
  if (!bus.good()) return 2;
  Forger forger(bus, junk_hz);
  bus.subscribe("IGMS_(ROBOT_STATE|HAPTIC_INPUT|SERVER_STATUS)", &Forger::onMessage, &forger)->setQueueCapacity(10000);
  const double end = now() + duration;
  const std::atomic<bool>& stop = igms::stopOnSignals();  // SIGTERM from the test: stop and report
  while (now() < end && !stop) {
    bus.handleTimeout(1);
    forger.tick();
  }
  forger.print(stderr);
  if (!stats.empty())
    if (std::FILE* f = std::fopen(stats.c_str(), "w")) {
      forger.print(f);
      std::fclose(f);
    }
  return 0;
}
