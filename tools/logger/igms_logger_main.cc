// igms-logger: records the LCM bus to standard LCM event logs.
//
//   igms-logger [-o NAME] [--increment] [--timestamp] [-c REGEX] [-v|--invert-channels]
//               [--split-mb N] [--split-s S] [--rotate N] [--flush-ms MS] [--queue N]
//               [--lcm-url URL] [--duration S] [--wait-session-s S] [--stats-file FILE]
//               [-q] [--verbose] [--slow-disk-us US]
//
// The receive handler never touches the disk: it copies the event into a
// bounded queue and a writer thread writes; events dropped because the queue
// was full are counted per channel and reported. The first event of each log
// file is the server's session_info (scene, model hash, build), held back for
// up to --wait-session-s while it has not been seen, and then its session
// files (every robot's model; session_files_t) once seen.
//
// With the bus key (--key-file) every message is checked as it arrives: what
// passes is recorded as it came (signature and all, so the check can be made
// again); what fails is recorded under "REFUSED:<reason>:<channel>", so the
// log keeps what arrived and whether its signature held, and nothing
// replays a refused message onto a real channel.

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <ctime>
#include <deque>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <mutex>
#include <regex>
#include <string>
#include <thread>
#include <vector>
#include <unistd.h>

#include "bus/bus_key.h"
#include "bus/message_verifier.h"
#include "bus/printable_name.h"
#include "bus/subscription.h"
#include "channels.h"
#include "core/cli/command_line.h"
#include "core/realtime/stop_signal.h"
#include "tools/eventlog/event_log.h"

namespace {


struct Options {
  std::string name;
  bool increment = false, timestamp = false, invert = false, quiet = false, verbose = false;
  std::string channel_regex = ".*";
  double split_mb = 0, split_s = 0, duration = 0, wait_session_s = 2.0, flush_ms = 100, slow_disk_us = 0;
  double silence_s = 3.0;    // say so when nothing has been heard for this long
  bool allow_empty = false;  // an empty log is an error unless asked for
  int rotate = 0;
  size_t queue = 20000;
  std::string lcm_url, stats_file, key_file;
};

bool exists(const std::string& p) { return access(p.c_str(), F_OK) == 0; }

// Names the files: NAME, or NAME.00, NAME.01, ... when splitting or incrementing.
class Naming {
 public:
  explicit Naming(const Options& o) : o_(o) {
    base_ = o.name;
    if (base_.empty() || o.timestamp) {
      char buf[64];
      const std::time_t now = std::time(nullptr);
      std::strftime(buf, sizeof buf, "%Y-%m-%d-%H%M%S", std::localtime(&now));
      base_ = (base_.empty() ? std::string("igms") : base_) + "-" + buf;
      if (o.name.empty()) base_ += ".lcmlog";
    }
  }
  std::string next() {
    const bool numbered = o_.increment || o_.split_mb > 0 || o_.split_s > 0;
    if (!numbered) return base_;
    for (;;) {
      char suffix[16];
      std::snprintf(suffix, sizeof suffix, ".%02d", n_++);
      const std::string p = base_ + suffix;
      if (!exists(p) || !o_.increment) return p;
    }
  }

 private:
  const Options& o_;
  std::string base_;
  int n_ = 0;
};

struct Queued {
  int64_t utime;
  std::string channel;
  std::vector<uint8_t> data;
};

class Logger {
 public:
  // Channels counted one by one in the report; beyond, in one row (a flood of names never grows the table).
  static constexpr size_t kMaxCountedChannels = 256;

  Logger(const Options& o, std::optional<igms::bus::BusKey> key)
      : o_(o), filter_(o.channel_regex), naming_(o), verifier_(std::move(key), "igms-logger") {
    verifier_.acceptReplays();  // a recorder: a replay on the bus is recorded as such, not refused
  }

  // Every message the filter takes, checked: the refused are recorded too, under REFUSED:why:channel.
  std::unique_ptr<igms::bus::RawSubscription> listen(lcm::LCM& bus) {
    igms::bus::RawSubscription::Options o;
    o.queue_capacity = 100000;
    o.wanted = [this](const std::string& channel) { return std::regex_match(channel, filter_) != o_.invert; };
    auto record = [this](const std::string& channel, const lcm::ReceiveBuffer& m, const igms::bus::Verdict& v) {
      onMessage(channel, m, v);
    };
    o.refused = record;
    return igms::bus::subscribeRaw(bus, verifier_, ".*", record, std::move(o));
  }

  void onMessage(const std::string& received_on, const lcm::ReceiveBuffer& m, const igms::bus::Verdict& checked) {
    // The bus thread: copy and queue, never the disk.
    const std::string channel =
        checked.accepted ? received_on : std::string("REFUSED:") + igms::bus::refusalName(checked.why) + ":" + received_on;
    std::lock_guard<std::mutex> lock(mutex_);
    ++received_[countedAs(received_, channel)];
    if (queue_.size() >= o_.queue) {
      ++dropped_[countedAs(dropped_, channel)];
      return;
    }
    const auto* p = static_cast<const uint8_t*>(m.data);
    queue_.push_back({m.recv_utime, channel, std::vector<uint8_t>(p, p + m.data_size)});
    if (channel == igms::channels::kSessionInfo) have_session_ = true;
    ready_.notify_one();
  }

  void writerLoop(const std::atomic<bool>& stop) {
    const auto start = std::chrono::steady_clock::now();
    auto since = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    // Hold the events back until the session info arrives (or the wait ends).
    while (!stop && !have_session_ && since() < o_.wait_session_s)
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    {
      std::lock_guard<std::mutex> lock(mutex_);
      // Move the newest session info (and the files that come with it) to the front.
      for (auto it = queue_.rbegin(); it != queue_.rend() && !(have_session_copy_ && have_files_copy_); ++it)
        if (it->channel == igms::channels::kSessionInfo && !have_session_copy_) {
          session_ = *it;
          have_session_copy_ = true;
        } else if (it->channel == igms::channels::kSessionFiles && !have_files_copy_) {
          session_files_ = *it;
          have_files_copy_ = true;
        }
    }
    if (!have_session_copy_ && !o_.quiet)
      std::fprintf(stderr, "igms-logger: no %s within %.1f s: the log will not re-simulate\n",
                   igms::channels::kSessionInfo, o_.wait_session_s);
    open();
    auto last_flush = std::chrono::steady_clock::now();
    double file_start = since();
    for (;;) {
      std::deque<Queued> batch;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        ready_.wait_for(lock, std::chrono::milliseconds(20), [&] { return !queue_.empty() || stop; });
        batch.swap(queue_);
        if (batch.empty() && stop) break;
      }
      for (const Queued& q : batch) {
        if (q.channel == igms::channels::kSessionInfo) {
          session_ = q;
          have_session_copy_ = true;
        } else if (q.channel == igms::channels::kSessionFiles) {
          session_files_ = q;
          have_files_copy_ = true;
        }
        if (o_.slow_disk_us > 0)  // a test hook: a disk this slow per event
          std::this_thread::sleep_for(std::chrono::microseconds(static_cast<int64_t>(o_.slow_disk_us)));
        writer_->write(q.utime, q.channel, q.data.data(), q.data.size());
        ++written_;
        if ((o_.split_mb > 0 && static_cast<double>(writer_->bytes()) >= o_.split_mb * 1048576.0) ||
            (o_.split_s > 0 && since() - file_start >= o_.split_s)) {
          open();
          file_start = since();
        }
      }
      if (std::chrono::steady_clock::now() - last_flush > std::chrono::duration<double, std::milli>(o_.flush_ms)) {
        writer_->flush();
        last_flush = std::chrono::steady_clock::now();
      }
    }
    writer_->flush();
  }

  int64_t receivedTotal() {
    std::lock_guard<std::mutex> lock(mutex_);
    int64_t n = 0;
    for (const auto& [c, k] : received_) n += k;
    return n;
  }

  void report(std::FILE* out, bool json) {
    std::lock_guard<std::mutex> lock(mutex_);
    int64_t received = 0, dropped = 0;
    for (const auto& [c, n] : received_) received += n;
    for (const auto& [c, n] : dropped_) dropped += n;
    if (json) {
      const igms::bus::VerifierCounts c = verifier_.counts();
      nlohmann::json refused = nlohmann::json::object();
      for (int k = 0; k < igms::bus::kRefusals; ++k)
        refused[igms::bus::refusalName(static_cast<igms::bus::Refusal>(k))] = c.refused[static_cast<size_t>(k)];
      const nlohmann::json stats = {{"received", received},
                                    {"written", written_},
                                    {"dropped", dropped},
                                    {"files", files_},
                                    {"dropped_by_channel", dropped_},
                                    {"keyed", verifier_.keyed()},
                                    {"verified", c.accepted},
                                    {"refused", refused}};
      // Channel names come off the bus: bytes that are not UTF-8 are replaced, never a throw.
      std::fprintf(out, "%s\n", stats.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
      return;
    }
    std::fprintf(out, "igms-logger: %lld received, %lld written, %lld dropped (queue full) in %zu file(s)\n",
                 static_cast<long long>(received), static_cast<long long>(written_), static_cast<long long>(dropped),
                 files_.size());
    for (const auto& [c, n] : dropped_)
      std::fprintf(out, "igms-logger:   dropped %lld on %s\n", static_cast<long long>(n),
                   igms::bus::printableName(c).c_str());  // a name off the bus: escaped
    std::fprintf(out, "igms-logger: bus: %s\n", verifier_.summary().c_str());
  }

 private:
  static std::string countedAs(const std::map<std::string, int64_t>& table, const std::string& channel) {
    return table.count(channel) || table.size() < kMaxCountedChannels ? channel : std::string("(other channels)");
  }

  void open() {
    if (writer_) writer_->flush();
    const std::string path = naming_.next();
    writer_ = std::make_unique<igms::log::LogWriter>(path);
    files_.push_back(path);
    if (!o_.quiet) std::fprintf(stderr, "igms-logger: writing %s\n", path.c_str());
    // Every file starts with what a replay needs.
    if (have_session_copy_) {
      writer_->write(session_.utime, session_.channel, session_.data.data(), session_.data.size());
      ++written_;
    }
    if (have_files_copy_) {
      writer_->write(session_files_.utime, session_files_.channel, session_files_.data.data(), session_files_.data.size());
      ++written_;
    }
    // Rotation: keep the newest N files.
    while (o_.rotate > 0 && static_cast<int>(files_.size()) > o_.rotate) {
      std::remove(files_.front().c_str());
      files_.erase(files_.begin());
    }
  }

  const Options& o_;
  std::regex filter_;
  Naming naming_;
  igms::bus::MessageVerifier verifier_;  // the bus thread's
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Queued> queue_;
  std::map<std::string, int64_t> received_, dropped_;
  std::atomic<bool> have_session_{false};
  bool have_session_copy_ = false, have_files_copy_ = false;
  Queued session_, session_files_;
  std::unique_ptr<igms::log::LogWriter> writer_;
  std::vector<std::string> files_;
  int64_t written_ = 0;
};

}  // namespace

// The command line into *o; -1 to go on, else the exit code.
int parseOptions(int argc, char** argv, Options* o) {
  CLI::App app{"", "igms-logger"};
  igms::cli::describe(app,
                      "Records LCM traffic to an event log (lcm-logger's format): a receive queue and a writer "
                      "thread, drops counted, the session info first. Run it inside scripts/netns_run.sh.");
  auto* output = app.add_option("-o,--output", o->name, "log file (default: a dated name in the current folder)");
  // As lcm-logger users type it: igms-logger session.lcmlog
  app.add_option("file", o->name, "log file (the same as -o)")->excludes(output);
  app.add_flag("--increment", o->increment, "add a number to the name instead of overwriting");
  app.add_flag("--timestamp", o->timestamp, "add the date and time to the name");
  app.add_option("-c,--channel", o->channel_regex, "channels to record (a regular expression)")
      ->check(CLI::Validator(
          [](std::string& re) -> std::string {
            try {
              std::regex test(re);
            } catch (const std::regex_error& e) {
              return std::string("bad channel regex: ") + e.what();
            }
            return "";
          },
          "REGEX"));
  app.add_flag("-v,--invert-channels", o->invert, "record the channels that do not match");
  app.add_option("--split-mb", o->split_mb, "start a new file after this many MB (0: never)")
      ->check(igms::cli::nonNegative("MB"));
  app.add_option("--split-s", o->split_s, "start a new file after this many seconds (0: never)")
      ->check(igms::cli::Seconds);
  app.add_option("--rotate", o->rotate, "keep only the newest N split files (0: all)")->check(CLI::NonNegativeNumber);
  app.add_option("--flush-ms", o->flush_ms, "flush to disk at least this often")->check(igms::cli::positive("MS"));
  app.add_option("--queue", o->queue, "messages the receive queue holds before it drops")->check(CLI::PositiveNumber);
  app.add_option("--lcm-url", o->lcm_url, "LCM URL (default udpm://239.255.76.67:7667?ttl=0)")
      ->check(igms::cli::LcmUrl);
  app.add_option("--duration", o->duration, "seconds to record (0: until stopped)")->check(igms::cli::Seconds);
  app.add_option("--wait-session-s", o->wait_session_s, "hold messages this long for the session info to come first")
      ->check(igms::cli::Seconds);
  app.add_option("--stats-file", o->stats_file, "write the final counts here as JSON");
  app.add_option("--key-file", o->key_file, igms::bus::kKeyFileHelp)->envname(igms::bus::kKeyFileEnv);
  app.add_option("--slow-disk-us", o->slow_disk_us, "(tests) sleep this long per write")
      ->check(igms::cli::nonNegative("US"));
  app.add_option("--silence-s", o->silence_s, "say so on stderr when nothing has been heard for this long")
      ->check(igms::cli::positive("S"));
  app.add_flag("--allow-empty", o->allow_empty, "exit 0 even when nothing was recorded (otherwise 1)");
  app.add_flag("-q,--quiet", o->quiet, "no summary on stderr");
  app.add_flag("--verbose", o->verbose, "counts on stderr every second");
  return igms::cli::parse(app, argc, argv);
}

int main(int argc, char** argv) {
  Options o;
  if (const int code = parseOptions(argc, argv, &o); code >= 0) return code;
  std::atomic<bool>& g_stop = igms::stopOnSignals();
  lcm::LCM bus(o.lcm_url.empty() ? igms::channels::kDefaultUrl : o.lcm_url + (o.lcm_url.find('?') == std::string::npos ? "?recv_buf_size=2097152" : "&recv_buf_size=2097152"));
  if (!bus.good()) {
    std::fprintf(stderr, "igms-logger: cannot open LCM\n");
    return 2;
  }
  std::optional<igms::bus::BusKey> key;
  try {
    key = igms::bus::busKeyFor("igms-logger", o.key_file);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-logger: %s\n", e.what());
    return 2;
  }
  Logger logger(o, key);
  const auto subscription = logger.listen(bus);
  std::atomic<bool> writer_stop{false};
  std::thread writer([&] {
    try {
      logger.writerLoop(writer_stop);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "igms-logger: %s\n", e.what());
      g_stop = true;
    }
  });
  const std::string url = o.lcm_url.empty() ? igms::channels::kDefaultUrl : o.lcm_url;
  const auto start = std::chrono::steady_clock::now();
  auto last_report = start, last_heard = start;
  int64_t heard = 0;
  bool silence_said = false;
  while (!g_stop) {
    bus.handleTimeout(50);
    const auto now = std::chrono::steady_clock::now();
    // Loud silence: a logger in the wrong network namespace or on the wrong URL hears nothing, and says so.
    if (const int64_t n = logger.receivedTotal(); n != heard) {
      heard = n;
      last_heard = now;
      silence_said = false;
    } else if (!silence_said && std::chrono::duration<double>(now - last_heard).count() >= o.silence_s) {
      std::fprintf(stderr,
                   "igms-logger: nothing heard on %s for %.0f s%s (is the server on this bus? processes started by "
                   "separate scripts/netns_run.sh calls do not hear each other: use scripts/sessions/bus.sh run)\n",
                   url.c_str(), o.silence_s, heard ? " since the last message" : "");
      silence_said = true;
    }
    if (o.duration > 0 && std::chrono::duration<double>(now - start).count() >= o.duration) break;
    if (o.verbose && now - last_report > std::chrono::seconds(1)) {
      logger.report(stderr, false);
      last_report = now;
    }
  }
  // Drain what LCM still holds, then stop the writer.
  while (bus.handleTimeout(0) > 0) {
  }
  writer_stop = true;
  writer.join();
  if (!o.quiet) logger.report(stderr, false);
  if (!o.stats_file.empty())
    if (std::FILE* f = std::fopen(o.stats_file.c_str(), "w")) {
      logger.report(f, true);
      std::fclose(f);
    }
  if (logger.receivedTotal() == 0 && !o.allow_empty) {
    std::fprintf(stderr, "igms-logger: the log is empty: nothing was heard on %s (--allow-empty to accept that)\n",
                 url.c_str());
    return 1;
  }
  return 0;
}
