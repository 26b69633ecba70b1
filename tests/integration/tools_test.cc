// The tools as processes on udpm in the private namespace: the logger's round
// trip (byte for byte, under a burst), its drop counting with a slow disk, the
// replayer's timing at speed 1, igms-spy's rates against a publisher of known
// rate, and a corrupt log reported with its byte offset.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <lcm/lcm-cpp.hpp>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "channels.h"
#include "igms/heartbeat_t.hpp"
#include "igms/session_info_t.hpp"
#include "tests/support/child_process.h"
#include "tests/support/test_models.h"
#include "tools/eventlog/event_log.h"

namespace igms::test {
namespace {

std::string url() { return std::string("udpm://239.255.76.67:") + std::getenv("IGMS_TEST_PORT") + "?ttl=0"; }
std::string tool(const char* name) { return std::string(std::getenv("IGMS_TOOLS_DIR")) + "/" + name; }
std::string temp(const std::string& name) { return ::testing::TempDir() + "/" + name; }

std::vector<uint8_t> payload(int k, int size) {
  std::vector<uint8_t> p(static_cast<size_t>(size));
  for (int i = 0; i < size; ++i) p[static_cast<size_t>(i)] = static_cast<uint8_t>(k * 31 + i);
  return p;
}

void publishSessionInfo(lcm::LCM& bus) {
  session_info_t s{};
  s.scene_path = "scenes/test.yaml";
  s.scene_text = "name: test";
  bus.publish(channels::kSessionInfo, &s);
}

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

// Waits for the logger to subscribe (it has no ready signal: give it time).
void settle() { std::this_thread::sleep_for(std::chrono::milliseconds(400)); }

TEST(Logger, WritesWhatWasPublishedByteForByteUnderABurst) {
  const std::string log = temp("roundtrip.lcmlog"), stats = temp("roundtrip.json");
  std::remove(log.c_str());
  lcm::LCM bus(url());
  {
    ChildProcess logger({tool("igms-logger"), "-o", log, "--lcm-url", url(), "-q", "--stats-file", stats,
                         "--wait-session-s", "5"});
    settle();
    // Events before the session info: the logger holds them back.
    for (int k = 0; k < 100; ++k) {
      const auto p = payload(k, 200);
      bus.publish("TEST_A", p.data(), static_cast<unsigned>(p.size()));
      std::this_thread::sleep_for(std::chrono::microseconds(500));
    }
    publishSessionInfo(bus);
    // A burst: 2000 back to back on two channels.
    for (int k = 100; k < 2100; ++k) {
      const auto p = payload(k, 100 + k % 300);
      bus.publish(k % 2 ? "TEST_A" : "TEST_B", p.data(), static_cast<unsigned>(p.size()));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    EXPECT_EQ(logger.stop(), 0);
  }
  const log::LogContents c = log::readAll(log);
  ASSERT_FALSE(c.damaged) << c.error;
  ASSERT_FALSE(c.events.empty());
  EXPECT_EQ(c.events[0].channel, channels::kSessionInfo) << "the first event records what a replay needs";
  // Every published payload, in order.
  int k = 0;
  for (const auto& e : c.events) {
    if (e.channel.rfind("TEST_", 0) != 0) continue;
    const auto expected = payload(k, k < 100 ? 200 : 100 + k % 300);
    ASSERT_EQ(e.channel, k < 100 ? "TEST_A" : (k % 2 ? "TEST_A" : "TEST_B")) << "event " << k;
    ASSERT_EQ(e.data, expected) << "event " << k;
    ++k;
  }
  EXPECT_EQ(k, 2100) << "nothing lost in the burst";
  const auto j = readJson(stats);
  EXPECT_EQ(j["dropped"], 0);
  std::remove(log.c_str());
}

TEST(Logger, CountsWhatASlowDiskMakesItDrop) {
  const std::string log = temp("slow.lcmlog"), stats = temp("slow.json");
  lcm::LCM bus(url());
  {
    ChildProcess logger({tool("igms-logger"), log, "--lcm-url", url(), "-q", "--stats-file", stats,
                         "--wait-session-s", "0", "--queue", "50", "--slow-disk-us", "2000", "-c", "SLOW_.*"});
    settle();
    for (int k = 0; k < 600; ++k) {
      const auto p = payload(k, 64);
      bus.publish("SLOW_A", p.data(), static_cast<unsigned>(p.size()));
      std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    logger.stop();
  }
  const auto j = readJson(stats);
  EXPECT_EQ(j["received"], 600);
  EXPECT_GT(j["dropped"].get<int>(), 0) << "a disk this slow cannot keep up";
  EXPECT_EQ(j["written"].get<int>() + j["dropped"].get<int>(), 600) << "every message written or counted";
  EXPECT_EQ(j["dropped_by_channel"]["SLOW_A"], j["dropped"]);
  const log::LogContents c = log::readAll(log);
  EXPECT_EQ(static_cast<int>(c.events.size()), j["written"].get<int>());
  std::remove(log.c_str());
}

struct Arrivals {
  std::mutex mutex;
  std::vector<double> times;
  void on(const lcm::ReceiveBuffer*, const std::string&) {
    std::lock_guard<std::mutex> l(mutex);
    times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count());
  }
};

TEST(Replay, PlaysAtRecordedTimingAtSpeedOneAndTwo) {
  const std::string log = temp("timing.lcmlog");
  {
    log::LogWriter w(log);
    for (int k = 0; k <= 20; ++k) {
      const auto p = payload(k, 32);
      w.write(1'000'000 + k * 50'000, "PLAY_T", p.data(), p.size());  // every 50 ms for 1 s
    }
  }
  for (double speed : {1.0, 2.0}) {
    lcm::LCM bus(url());
    Arrivals a;
    bus.subscribe("PLAY_T", &Arrivals::on, &a);
    std::atomic<bool> stop{false};
    std::thread t([&] {
      while (!stop) bus.handleTimeout(5);
    });
    ChildProcess player({tool("igms-replay"), "play", log, "--lcm-url", url(), "--speed", std::to_string(speed)});
    EXPECT_EQ(player.wait(std::chrono::seconds(10)), 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    stop = true;
    t.join();
    ASSERT_EQ(a.times.size(), 21u) << "speed " << speed;
    const double span = a.times.back() - a.times.front();
    EXPECT_NEAR(span, 1.0 / speed, 0.02) << "speed " << speed;
    // Each arrival against the schedule, taken from the median offset: measured from the first arrival
    // alone, one late first event (the receiver's thread scheduled late) moved every other by as much.
    std::vector<double> offset(a.times.size());
    for (size_t k = 0; k < a.times.size(); ++k) offset[k] = a.times[k] - 0.05 * static_cast<double>(k) / speed;
    std::vector<double> sorted = offset;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double median = sorted[sorted.size() / 2];
    // The arrival time includes the receiving thread's wake-up: on a loaded 2-core machine one of 21 came
    // 14 ms late while the player was on time. A player that drifts or misreads the speed moves many.
    std::vector<double> error;
    for (double o : offset) error.push_back(std::abs(o - median));
    std::sort(error.begin(), error.end());
    EXPECT_LE(error[error.size() - 2], 0.01) << "all but one event within 10 ms of its time, speed " << speed;
    EXPECT_LE(error.back(), 0.03) << "every event within 30 ms of its time, speed " << speed;
  }
  std::remove(log.c_str());
}

TEST(Spy, RatesMatchAPublisherOfKnownRate) {
  lcm::LCM bus(url());
  std::atomic<bool> stop{false};
  std::thread publisher([&] {
    heartbeat_t h;
    h.process = "test";
    auto next = std::chrono::steady_clock::now();
    for (int64_t k = 0; !stop; ++k) {
      h.seq = k;
      if (k % 50 == 49) ++h.seq;  // a seq gap every 50
      bus.publish(channels::kHeartbeat, &h);
      next += std::chrono::microseconds(5000);  // 200 Hz
      std::this_thread::sleep_until(next);
    }
  });
  const std::string out = temp("spy.json");
  ChildProcess spy({"/bin/sh", "-c", tool("igms-spy") + " --lcm-url '" + url() + "' --once --json --window 2 > " + out});
  EXPECT_EQ(spy.wait(std::chrono::seconds(10)), 0);
  stop = true;
  publisher.join();
  const auto j = readJson(out);
  const auto& hb = j[channels::kHeartbeat];
  EXPECT_NEAR(hb["rate_hz"].get<double>(), 200.0, 10.0);
  EXPECT_EQ(hb["type"], "heartbeat_t");
  EXPECT_EQ(hb["undecodable"], 0);
  EXPECT_GE(hb["seq_gaps"].get<int>(), 5);
}

TEST(Replay, ACorruptLogIsReportedWithItsByteOffset) {
  const std::string log = temp("corrupt.lcmlog"), err = temp("corrupt.err");
  {
    log::LogWriter w(log);
    const auto p = payload(1, 32);
    for (int k = 0; k < 4; ++k) w.write(k, "C", p.data(), p.size());
  }
  {
    std::ofstream f(log, std::ios::app | std::ios::binary);
    f << "garbage";
  }
  ChildProcess info({"/bin/sh", "-c", tool("igms-replay") + " info " + log + " 2> " + err + " > /dev/null"});
  EXPECT_EQ(info.wait(std::chrono::seconds(5)), 3);
  const std::string message = readFile(err);
  EXPECT_NE(message.find("byte 244"), std::string::npos) << message;  // 4 events of 28 + 1 + 32 bytes
  EXPECT_NE(message.find("using the 4 events before the damage"), std::string::npos) << message;
  std::remove(log.c_str());
}

// Export into a folder that does not exist yet (out/x with no out/), and every CSV starts with its header.
TEST(Replay, ExportMakesItsFolderAndEveryCsvHasAHeader) {
  const std::string dir = temp("export_parent") + "/nested/export";
  ChildProcess ex({"/bin/sh", "-c",
                   tool("igms-replay") + " export " + sourceDir() + "/tests/replay/data/push.lcmlog " + dir +
                       " 2> /dev/null"});
  ASSERT_EQ(ex.wait(std::chrono::seconds(20)), 0);
  for (const auto& [file, first] : std::vector<std::pair<std::string, std::string>>{
           {"states.csv", "t,seq,input_seq,mode,q0"},
           {"inputs.csv", "utime,seq,mode,tip_x"},
           {"client_status.csv", "utime,cycles,rate_hz"},
           {"server_status.csv", "t,steps,rate_hz"}}) {
    std::ifstream in(dir + "/" + file);
    std::string header;
    ASSERT_TRUE(std::getline(in, header)) << file;
    EXPECT_EQ(header.rfind(first, 0), 0u) << file << ": " << header;
  }
}

// A message that does not decode as its channel's type (here a status and a state of the wrong
// shape, as a log recorded by another version of igms holds) is left out of the CSVs, and the export
// says how many, per channel.
TEST(Replay, ExportCountsTheMessagesThatDoNotDecode) {
  const std::string log = temp("foreign.lcmlog"), err = temp("foreign.err"), dir = temp("foreign_export");
  {
    log::LogWriter w(log);
    const auto p = payload(3, 40);
    w.write(1, channels::kServerStatus, p.data(), p.size());
    w.write(2, channels::kServerStatus, p.data(), p.size());
    w.write(3, channels::kRobotState, p.data(), p.size());
  }
  ChildProcess ex({"/bin/sh", "-c", tool("igms-replay") + " export " + log + " " + dir + " 2> " + err + " > /dev/null"});
  EXPECT_EQ(ex.wait(std::chrono::seconds(20)), 0);
  const std::string message = readFile(err);
  EXPECT_NE(message.find("left out 2 messages on " + std::string(channels::kServerStatus)), std::string::npos) << message;
  EXPECT_NE(message.find("left out 1 messages on " + std::string(channels::kRobotState)), std::string::npos) << message;
  std::ifstream status(dir + "/server_status.csv");
  std::string header, row;
  ASSERT_TRUE(std::getline(status, header));
  EXPECT_FALSE(std::getline(status, row)) << "no row from a status that did not decode";
  std::remove(log.c_str());
}

}  // namespace
}  // namespace igms::test
