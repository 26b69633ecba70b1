// The lcm-gen mechanism: a generated type encodes, travels over an in-process
// LCM (memq://, no network) and decodes to the same values.
#include <gtest/gtest.h>

#include <lcm/lcm-cpp.hpp>

#include "igms/heartbeat_t.hpp"

namespace {

struct Receiver {
  void on(const lcm::ReceiveBuffer*, const std::string& channel, const igms::heartbeat_t* msg) {
    last = *msg;
    last_channel = channel;
    ++count;
  }
  igms::heartbeat_t last{};
  std::string last_channel;
  int count = 0;
};

TEST(LcmTypes, HeartbeatRoundTripsOverMemq) {
  lcm::LCM bus("memq://");
  ASSERT_TRUE(bus.good());
  Receiver r;
  bus.subscribe("IGMS_HEARTBEAT", &Receiver::on, &r);
  igms::heartbeat_t msg;
  msg.utime = 1234567890123;
  msg.seq = 42;
  msg.process = "igms-test";
  msg.pid = 77;
  ASSERT_EQ(bus.publish("IGMS_HEARTBEAT", &msg), 0);
  ASSERT_GT(bus.handleTimeout(100), 0);
  EXPECT_EQ(r.count, 1);
  EXPECT_EQ(r.last_channel, "IGMS_HEARTBEAT");
  EXPECT_EQ(r.last.utime, msg.utime);
  EXPECT_EQ(r.last.seq, 42);
  EXPECT_EQ(r.last.process, "igms-test");
  EXPECT_EQ(r.last.pid, 77);
}

TEST(LcmTypes, DecodingATruncatedBufferFails) {
  igms::heartbeat_t msg;
  msg.process = "x";
  std::vector<uint8_t> buf(static_cast<size_t>(msg.getEncodedSize()));
  ASSERT_EQ(msg.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  igms::heartbeat_t back;
  EXPECT_LT(back.decode(buf.data(), 0, static_cast<int>(buf.size()) - 3), 0);
  EXPECT_EQ(back.decode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
}

}  // namespace
