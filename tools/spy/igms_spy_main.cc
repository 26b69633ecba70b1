// igms-spy: an lcm-spy for terminals. Per channel: messages, rate, jitter,
// bandwidth, seq gaps, undecodable messages and the latest decoded igms
// message; plus the server's and the client's health.
//   igms-spy [--lcm-url URL] [--once] [--window S] [--json] [--channel REGEX]

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <mutex>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "bus/bus_key.h"
#include "bus/message_verifier.h"
#include "bus/printable_name.h"
#include "bus/subscription.h"
#include "igms/bus_status_t.hpp"
#include "igms/device_force_t.hpp"
#include "igms/device_reading_t.hpp"
#include "igms/device_status_t.hpp"
#include "channels.h"
#include "core/cli/command_line.h"
#include "core/realtime/stop_signal.h"
#include "igms/client_status_t.hpp"
#include "igms/command_t.hpp"
#include "igms/contacts_t.hpp"
#include "igms/haptic_input_t.hpp"
#include "igms/heartbeat_t.hpp"
#include "igms/robot_state_t.hpp"
#include "igms/server_status_t.hpp"
#include "igms/session_files_t.hpp"
#include "igms/session_info_t.hpp"
#include "igms/trajectory_t.hpp"
#include "safe_decode.h"

namespace {


double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// An igms message: its type by fingerprint, a one-line summary, its seq.
template <typename T>
bool summarize(const uint8_t* d, int n, std::string* name, std::string* line, int64_t* seq);

#define IGMS_SEQ_TYPE(T, FMT, ...)                                                                 \
  template <>                                                                                      \
  bool summarize<igms::T>(const uint8_t* d, int n, std::string* name, std::string* line, int64_t* seq) { \
    igms::T m;                                                                                     \
    if (!igms::safeDecode(d, n, &m)) return false;                                                       \
    *name = #T;                                                                                    \
    char buf[384];                                                                                 \
    std::snprintf(buf, sizeof buf, FMT, __VA_ARGS__);                                              \
    *line = buf;                                                                                   \
    *seq = m.seq;                                                                                  \
    return true;                                                                                   \
  }

IGMS_SEQ_TYPE(robot_state_t, "t=%.3f q0=%.3f mode=%d hands=%d |F|=%.2f N |T|=%.3f N m step=%d us", m.sim_time,
              m.nq ? m.q[0] : 0.0, int{m.mode}, m.nhands,
              std::sqrt(m.interaction_force[0] * m.interaction_force[0] + m.interaction_force[1] * m.interaction_force[1] +
                        m.interaction_force[2] * m.interaction_force[2]),
              std::sqrt(m.interaction_torque[0] * m.interaction_torque[0] +
                        m.interaction_torque[1] * m.interaction_torque[1] +
                        m.interaction_torque[2] * m.interaction_torque[2]),
              m.step_us)
IGMS_SEQ_TYPE(haptic_input_t, "client %d mode %d tip (%.3f %.3f %.3f)", m.client_id, int{m.mode}, m.tip_position[0],
              m.tip_position[1], m.tip_position[2])
IGMS_SEQ_TYPE(server_status_t,
              "%s %.0f Hz step p50/p99 %.1f/%.1f us overruns %lld rejected %lld collisions %lld clients %d (active %d)"
              " contact solves %lld unconverged %lld slips unturned %lld linearised %lld sweeps<=%d",
              m.state.c_str(), m.rate_hz, m.step_us_p50, m.step_us_p99,
              static_cast<long long>(m.overruns), static_cast<long long>(m.inputs_rejected),
              static_cast<long long>(m.collisions), m.nclients,
              static_cast<int>(std::count(m.client_active.begin(), m.client_active.end(), true)),
              static_cast<long long>(m.contact_solves), static_cast<long long>(m.contact_unconverged),
              static_cast<long long>(m.contact_slips_unturned),
              static_cast<long long>(m.contact_linearised), m.contact_sweeps_max)
IGMS_SEQ_TYPE(client_status_t, "%s %.0f Hz rtt p50/p99 %.0f/%.0f us misses %lld fallbacks %lld scale %.2f",
              m.state.c_str(), m.rate_hz, m.rtt_us_p50, m.rtt_us_p99, static_cast<long long>(m.deadline_misses),
              static_cast<long long>(m.fallbacks), m.force_scale)
IGMS_SEQ_TYPE(command_t, "kind %d text '%s'", int{m.kind}, m.text.c_str())
IGMS_SEQ_TYPE(heartbeat_t, "%s pid %d", m.process.c_str(), m.pid)

// The contacts: how many, the deepest overlap and the largest force.
double largestForce(const igms::contacts_t& m) {
  double f = 0.0;
  for (int k = 0; k < m.ncontacts; ++k)
    f = std::max(f, std::sqrt(m.force[k][0] * m.force[k][0] + m.force[k][1] * m.force[k][1] + m.force[k][2] * m.force[k][2]));
  return f;
}
double deepest(const igms::contacts_t& m) {
  double d = 0.0;
  for (int k = 0; k < m.ncontacts; ++k) d = std::min(d, m.distance[k]);
  return -d;
}
// Sent every few steps: its seq is the step's, so gaps are not losses (seq -1).
template <>
bool summarize<igms::contacts_t>(const uint8_t* d, int n, std::string* name, std::string* line, int64_t* seq) {
  igms::contacts_t m{};
  if (!igms::safeDecode(d, n, &m)) return false;
  *name = "contacts_t";
  char buf[256];
  std::snprintf(buf, sizeof buf, "t=%.3f contacts %d (sent %d) deepest %.2f mm largest |f| %.2f N dropped %lld",
                m.sim_time, m.total, m.ncontacts, deepest(m) * 1e3, largestForce(m), static_cast<long long>(m.dropped));
  *line = buf;
  *seq = -1;
  return true;
}

template <>
bool summarize<igms::session_info_t>(const uint8_t* d, int n, std::string* name, std::string* line, int64_t* seq) {
  igms::session_info_t m{};
  if (!igms::safeDecode(d, n, &m)) return false;
  *name = "session_info_t";
  *line = "scene " + m.scene_path + ", " + m.clock + ", " + m.build_version;
  *seq = -1;
  return true;
}
template <>
bool summarize<igms::session_files_t>(const uint8_t* d, int n, std::string* name, std::string* line, int64_t* seq) {
  igms::session_files_t m{};
  if (!igms::safeDecode(d, n, &m)) return false;
  *name = "session_files_t";
  int64_t bytes = 0, meshes = m.nmeshes;
  std::string robots;
  for (const auto& r : m.robots) {
    bytes += r.model_size;
    meshes += r.nmeshes;
    robots += (robots.empty() ? "" : ", ") + (r.robot.empty() ? std::string("robot") : r.robot);
  }
  *line = std::to_string(m.nrobots) + " models (" + robots + "; " + std::to_string(bytes) + " bytes), " +
          std::to_string(meshes) + " mesh hashes";
  *seq = -1;
  return true;
}
template <>
bool summarize<igms::trajectory_t>(const uint8_t* d, int n, std::string* name, std::string* line, int64_t* seq) {
  igms::trajectory_t m{};
  if (!igms::safeDecode(d, n, &m)) return false;
  *name = "trajectory_t";
  *line = std::to_string(m.npoints) + " points of " + std::to_string(m.nq) + " coordinates";
  *seq = -1;
  return true;
}
// Every program's, once a second: the message checks' counts (several programs share the channel).
template <>
bool summarize<igms::bus_status_t>(const uint8_t* d, int n, std::string* name, std::string* line, int64_t* seq) {
  igms::bus_status_t m{};
  if (!igms::safeDecode(d, n, &m)) return false;
  *name = "bus_status_t";
  int64_t refused = 0;
  for (int64_t r : m.refused) refused += r;
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s %s: accepted %lld refused %lld (unsigned %lld, bad signature %lld, replayed %lld)",
                igms::bus::printableName(m.program, 40).c_str(), m.keyed ? "signs" : "no key", static_cast<long long>(m.accepted),
                static_cast<long long>(refused), static_cast<long long>(m.refused[0]),
                static_cast<long long>(m.refused[1]), static_cast<long long>(m.refused[2]));
  *line = buf;
  *seq = -1;
  return true;
}

// The haptic client's device, once a second: its calls' times, overruns, refused readings, limits.
template <>
bool summarize<igms::device_status_t>(const uint8_t* d, int n, std::string* name, std::string* line, int64_t* seq) {
  igms::device_status_t m{};
  if (!igms::safeDecode(d, n, &m)) return false;
  *name = "device_status_t";
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "%s: read p99 %.0f us max %.0f us, write p99 %.0f us max %.0f us, %lld overruns, %lld failed, "
                "%lld readings refused, max force %.2f N",
                igms::bus::printableName(m.device, 60).c_str(), m.read_us_p99, m.read_us_max, m.write_us_p99, m.write_us_max,
                static_cast<long long>(m.overruns), static_cast<long long>(m.failed_calls),
                static_cast<long long>(m.readings_rejected), m.max_force);
  *line = buf;
  *seq = -1;
  return true;
}
// A device on the bus (igms-haptic --device lcm): its readings, and the forces back.
template <>
bool summarize<igms::device_reading_t>(const uint8_t* d, int n, std::string* name, std::string* line, int64_t* seq) {
  igms::device_reading_t m{};
  if (!igms::safeDecode(d, n, &m)) return false;
  *name = "device_reading_t";
  char buf[200];
  std::snprintf(buf, sizeof buf, "tip (%.4f, %.4f, %.4f) m, buttons %d%s", m.position[0], m.position[1],
                m.position[2], m.buttons, m.has_orientation ? ", 6-dof" : "");
  *line = buf;
  *seq = m.seq;
  return true;
}
template <>
bool summarize<igms::device_force_t>(const uint8_t* d, int n, std::string* name, std::string* line, int64_t* seq) {
  igms::device_force_t m{};
  if (!igms::safeDecode(d, n, &m)) return false;
  *name = "device_force_t";
  char buf[200];
  std::snprintf(buf, sizeof buf, "force (%.3f, %.3f, %.3f) N for reading %lld (%.0f us old at the cycle)",
                m.force[0], m.force[1], m.force[2], static_cast<long long>(m.reading_seq),
                static_cast<double>(m.reading_age_us));
  *line = buf;
  *seq = m.seq;
  return true;
}

struct Decoder {
  int64_t hash;
  bool (*fn)(const uint8_t*, int, std::string*, std::string*, int64_t*);
};

template <typename T>
Decoder decoder() {
  return {T::getHash(), &summarize<T>};
}

struct Channel {
  int64_t count = 0, bytes = 0, undecodable = 0, seq_gaps = 0, last_seq = -1;
  int64_t refused = 0;   // failed the message check (with a bus key): counted, never decoded
  bool signed_ = false;  // the newest message carried a signature
  std::vector<double> arrivals;  // within the window
  std::vector<int64_t> sizes;
  std::string type, latest;
  bool igms = false;
};

class Spy {
 public:
  // Channels counted one by one; beyond, in one row (a flood of names never grows the table).
  static constexpr size_t kMaxChannels = 512;
  static constexpr const char* kOtherChannels = "(other channels)";

  Spy(const std::string& filter, std::optional<igms::bus::BusKey> key)
      : filter_(filter), verifier_(std::move(key), "igms-spy") {
    verifier_.acceptReplays();  // a monitor: a replay on the bus is shown, not refused
    decoders_ = {decoder<igms::robot_state_t>(), decoder<igms::haptic_input_t>(), decoder<igms::server_status_t>(),
                 decoder<igms::client_status_t>(), decoder<igms::command_t>(), decoder<igms::heartbeat_t>(),
                 decoder<igms::session_info_t>(), decoder<igms::trajectory_t>(), decoder<igms::contacts_t>(),
                 decoder<igms::bus_status_t>(), decoder<igms::device_status_t>(), decoder<igms::device_reading_t>(),
                 decoder<igms::device_force_t>(), decoder<igms::session_files_t>()};
  }
  // Every message on the bus, checked: the accepted decoded, the refused counted.
  std::unique_ptr<igms::bus::RawSubscription> listen(lcm::LCM& bus) {
    igms::bus::RawSubscription::Options o;
    o.queue_capacity = 100000;
    o.wanted = [this](const std::string& channel) { return std::regex_match(channel, filter_); };
    auto take = [this](const std::string& channel, const lcm::ReceiveBuffer& m, const igms::bus::Verdict& v) {
      onMessage(channel, static_cast<const uint8_t*>(m.data), m.data_size, v);
    };
    o.refused = take;
    return igms::bus::subscribeRaw(bus, verifier_, ".*", take, std::move(o));
  }
  void onMessage(const std::string& channel, const uint8_t* d, size_t size, const igms::bus::Verdict& checked) {
    const double t = now();
    std::lock_guard<std::mutex> lock(mutex_);
    const bool counted = channels_.count(channel) > 0 || channels_.size() < kMaxChannels;
    Channel& c = channels_[counted ? channel : std::string(kOtherChannels)];
    ++c.count;
    c.bytes += size;
    c.arrivals.push_back(t);
    c.sizes.push_back(size);
    igms::bus::Trailer trailer;
    c.signed_ = igms::bus::findTrailer(d, size, &trailer);
    if (!checked.accepted) {
      ++c.refused;
      return;
    }
    const int n = static_cast<int>(checked.payload_bytes);
    // Which igms type, by the fingerprint in the first 8 bytes.
    const bool igms_channel = channel.rfind("IGMS_", 0) == 0;
    int64_t hash = 0;
    if (n >= 8)
      for (int k = 0; k < 8; ++k) hash = (hash << 8) | d[k];
    for (const auto& dec : decoders_) {
      if (dec.hash != hash) continue;
      std::string name, line;
      int64_t seq = -1;
      if (dec.fn(d, n, &name, &line, &seq)) {
        c.type = name;
        c.latest = line;
        c.igms = true;
        if (seq >= 0 && c.last_seq >= 0 && seq > c.last_seq + 1) c.seq_gaps += seq - c.last_seq - 1;
        if (seq >= 0) c.last_seq = seq;
        return;
      }
    }
    if (igms_channel) ++c.undecodable;  // an igms channel carrying something else
  }
  // The snapshot over the last `window` seconds.
  void print(double window, bool json, std::FILE* out) {
    std::lock_guard<std::mutex> lock(mutex_);
    const double t = now();
    nlohmann::json snapshot = nlohmann::json::object();
    bool first = true;
    for (auto& [name, c] : channels_) {
      // Keep only the window's arrivals.
      size_t keep = 0;
      while (keep < c.arrivals.size() && c.arrivals[keep] < t - window) ++keep;
      c.arrivals.erase(c.arrivals.begin(), c.arrivals.begin() + static_cast<long>(keep));
      c.sizes.erase(c.sizes.begin(), c.sizes.begin() + static_cast<long>(keep));
      const double rate = static_cast<double>(c.arrivals.size()) / window;
      double bw = 0.0;
      for (auto s : c.sizes) bw += static_cast<double>(s);
      bw /= window;
      std::vector<double> gaps;
      for (size_t i = 1; i < c.arrivals.size(); ++i) gaps.push_back(c.arrivals[i] - c.arrivals[i - 1]);
      double jitter = 0.0;  // p99 of |gap - median gap|, ms
      if (gaps.size() > 2) {
        std::vector<double> g = gaps;
        std::nth_element(g.begin(), g.begin() + g.size() / 2, g.end());
        const double med = g[g.size() / 2];
        for (auto& x : gaps) x = std::abs(x - med);
        std::sort(gaps.begin(), gaps.end());
        jitter = 1e3 * gaps[static_cast<size_t>(0.99 * static_cast<double>(gaps.size() - 1))];
      }
      if (json) {
        snapshot[name] = {{"count", c.count},       {"rate_hz", rate},       {"jitter_ms", jitter},
                          {"bytes_per_s", bw},      {"seq_gaps", c.seq_gaps}, {"undecodable", c.undecodable},
                          {"type", c.type},         {"refused", c.refused},   {"signed", c.signed_}};
      } else {
        if (first)
          std::fprintf(out, "%-24s %9s %9s %9s %10s %6s %6s %7s  %s\n", "channel", "count", "rate Hz", "jitter ms",
                       "kB/s", "gaps", "bad", "refused", "type / latest");
        // Names and lines come off the bus: escaped, so no terminal sequence from the wire is printed.
        std::fprintf(out, "%-24s %9lld %9.1f %9.3f %10.1f %6lld %6lld %7lld  %s%s\n",
                     igms::bus::printableName(name).c_str(),
                     static_cast<long long>(c.count), rate, jitter, bw / 1e3, static_cast<long long>(c.seq_gaps),
                     static_cast<long long>(c.undecodable), static_cast<long long>(c.refused),
                     c.type.empty() ? "(not an igms type)" : c.type.c_str(), c.signed_ ? " (signed)" : "");
        if (!c.latest.empty()) std::fprintf(out, "%-24s   %s\n", "", igms::bus::printableName(c.latest, 400).c_str());
      }
      first = false;
    }
    // Channel names come off the bus: bytes that are not UTF-8 are replaced, never a throw.
    if (json) std::fprintf(out, "%s\n", snapshot.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
    if (first && !json) std::fprintf(out, "(no messages yet)\n");
  }

  // Messages heard on the channels the filter keeps, since start.
  int64_t heard() {
    std::lock_guard<std::mutex> lock(mutex_);
    int64_t n = 0;
    for (const auto& [name, c] : channels_) n += c.count;
    return n;
  }

 private:
  std::regex filter_;
  igms::bus::MessageVerifier verifier_;  // the bus thread's
  std::mutex mutex_;
  std::map<std::string, Channel> channels_;
  std::vector<Decoder> decoders_;
};

}  // namespace

int main(int argc, char** argv) {
  std::string url, filter = ".*";
  bool once = false, json = false;
  double window = 1.0;
  CLI::App app{"", "igms-spy"};
  igms::cli::describe(app,
                      "A terminal monitor of the bus (lcm-spy style): rate, bandwidth and the decoded igms fields per "
                      "channel. Run it inside scripts/netns_run.sh.");
  app.add_option("--lcm-url", url, "LCM URL (default udpm://239.255.76.67:7667?ttl=0)")->check(igms::cli::LcmUrl);
  app.add_flag("--once", once, "print one window and exit");
  app.add_option("--window", window, "seconds each figure is measured over")->check(igms::cli::positive("SECONDS"));
  app.add_flag("--json", json, "JSON instead of a table");
  app.add_option("--channel", filter, "only these channels (a regular expression)");
  std::string key_file;
  app.add_option("--key-file", key_file,
                 "check every message with the bus key in this file: what fails is counted as refused, not "
                 "decoded (default: $IGMS_KEY_FILE)")
      ->envname(igms::bus::kKeyFileEnv);
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  std::atomic<bool>& g_stop = igms::stopOnSignals();
  lcm::LCM bus(url.empty() ? igms::channels::kDefaultUrl : url);
  if (!bus.good()) {
    std::fprintf(stderr, "igms-spy: cannot open LCM\n");
    return 2;
  }
  std::optional<igms::bus::BusKey> key;
  try {
    if (!key_file.empty()) key = igms::bus::loadBusKey(key_file);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-spy: %s\n", e.what());
    return 2;
  }
  Spy spy(filter, key);
  const auto subscription = spy.listen(bus);
  const double start = now();
  double next_draw = start + 0.5;
  const std::string where = url.empty() ? igms::channels::kDefaultUrl : url;
  // Loud silence: a spy in the wrong network namespace or on the wrong URL hears nothing, and says so.
  const std::string silence = "nothing heard on " + where +
                              " (is the server on this bus? processes started by separate scripts/netns_run.sh calls "
                              "do not hear each other: use scripts/sessions/bus.sh run)";
  int64_t heard = 0;
  double last_heard = start;
  while (!g_stop) {
    bus.handleTimeout(20);
    const double t = now();
    if (const int64_t n = spy.heard(); n != heard) {
      heard = n;
      last_heard = t;
    }
    if (once && t - start >= window) {
      spy.print(window, json, stdout);
      if (heard == 0) {
        std::fprintf(stderr, "igms-spy: %s in %.1f s\n", silence.c_str(), window);
        return 1;
      }
      return 0;
    }
    if (!once && t >= next_draw) {
      std::printf("\033[H\033[2J");  // refresh in place
      std::printf("igms-spy on %s (window %.1f s; Ctrl-C quits)\n\n", where.c_str(), window);
      spy.print(window, json, stdout);
      if (t - last_heard >= 3.0) std::printf("\n%s for %.0f s\n", silence.c_str(), t - last_heard);
      std::fflush(stdout);
      next_draw = t + 0.5;
    }
  }
  return 0;
}
