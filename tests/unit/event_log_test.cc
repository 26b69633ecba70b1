// Our event-log reader and writer against LCM's own (lcm::LogFile), both
// ways, and damaged logs: the error names the byte offset, and the events
// before the damage stay usable.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <lcm/lcm-cpp.hpp>

#include "tools/eventlog/event_log.h"

namespace igms::log {
namespace {

std::string temp(const char* name) { return ::testing::TempDir() + "/" + name; }

std::vector<uint8_t> payload(int k) {
  std::vector<uint8_t> p(static_cast<size_t>(10 + k % 50));
  for (size_t i = 0; i < p.size(); ++i) p[i] = static_cast<uint8_t>(k * 7 + i);
  return p;
}

TEST(EventLog, WhatWeWriteLcmReadsBackByteForByte) {
  const std::string path = temp("ours.lcmlog");
  {
    LogWriter w(path);
    for (int k = 0; k < 100; ++k) {
      const auto p = payload(k);
      w.write(1000 + k, k % 2 ? "CHAN_A" : "CHAN_BB", p.data(), p.size());
    }
  }
  lcm::LogFile lf(path, "r");
  ASSERT_TRUE(lf.good());
  int k = 0;
  while (const lcm::LogEvent* e = lf.readNextEvent()) {
    EXPECT_EQ(e->eventnum, k);
    EXPECT_EQ(e->timestamp, 1000 + k);
    EXPECT_EQ(e->channel, k % 2 ? "CHAN_A" : "CHAN_BB");
    const auto p = payload(k);
    ASSERT_EQ(e->datalen, static_cast<int32_t>(p.size()));
    EXPECT_EQ(0, std::memcmp(e->data, p.data(), p.size()));
    ++k;
  }
  EXPECT_EQ(k, 100);
  std::remove(path.c_str());
}

TEST(EventLog, WeReadWhatLcmWrites) {
  const std::string path = temp("theirs.lcmlog");
  {
    lcm::LogFile lf(path, "w");
    for (int k = 0; k < 50; ++k) {
      auto p = payload(k);
      lcm::LogEvent e;
      e.eventnum = k;
      e.timestamp = 77 + k;
      e.channel = "X";
      e.datalen = static_cast<int32_t>(p.size());
      e.data = p.data();
      lf.writeEvent(&e);
    }
  }
  const LogContents c = readAll(path);
  EXPECT_FALSE(c.damaged);
  ASSERT_EQ(c.events.size(), 50u);
  EXPECT_EQ(c.events[49].utime, 77 + 49);
  EXPECT_EQ(c.events[49].data, payload(49));
  std::remove(path.c_str());
}

TEST(EventLog, DamageIsReportedAtItsByteOffsetAndEarlierEventsSurvive) {
  const std::string path = temp("damaged.lcmlog");
  uint64_t fifth = 0;
  {
    LogWriter w(path);
    for (int k = 0; k < 10; ++k) {
      if (k == 5) fifth = w.bytes();
      const auto p = payload(k);
      w.write(k, "C", p.data(), p.size());
    }
  }
  // Overwrite the sync word of the sixth event.
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(fifth));
    f.write("XXXX", 4);
  }
  const LogContents c = readAll(path);
  EXPECT_TRUE(c.damaged);
  EXPECT_EQ(c.error_offset, fifth);
  EXPECT_NE(c.error.find("byte " + std::to_string(fifth) + ": bad sync word"), std::string::npos) << c.error;
  EXPECT_EQ(c.events.size(), 5u);

  // A truncated last event.
  {
    LogWriter w(path);
    for (int k = 0; k < 3; ++k) {
      const auto p = payload(k);
      w.write(k, "C", p.data(), p.size());
    }
  }
  {
    std::ifstream in(path, std::ios::binary);
    std::string all((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::ofstream(path, std::ios::binary | std::ios::trunc) << all.substr(0, all.size() - 5);
  }
  const LogContents t = readAll(path);
  EXPECT_TRUE(t.damaged);
  EXPECT_NE(t.error.find("truncated event"), std::string::npos) << t.error;
  EXPECT_EQ(t.events.size(), 2u);
  std::remove(path.c_str());
  EXPECT_THROW(LogReader("/nonexistent/x.lcmlog"), LogError);
}

}  // namespace
}  // namespace igms::log
