// LCM over UDP multicast (udpm://, ttl=0) inside the private network namespace
// that scripts/netns_run.sh makes: a heartbeat published is received. ctest
// runs this binary through the wrapper, on a port of its own.
#include <gtest/gtest.h>

#include <cstdlib>
#include <lcm/lcm-cpp.hpp>
#include <string>

#include "igms/heartbeat_t.hpp"

namespace {

struct Receiver {
  void on(const lcm::ReceiveBuffer*, const std::string&, const igms::heartbeat_t* msg) { seq = msg->seq; ++count; }
  int64_t seq = -1;
  int count = 0;
};

TEST(UdpmLoopback, HeartbeatArrivesInsideThePrivateNamespace) {
  ASSERT_STREQ(std::getenv("IGMS_IN_NETNS"), "1") << "run through scripts/netns_run.sh";
  const std::string url = std::string("udpm://239.255.76.67:") + std::getenv("IGMS_TEST_PORT") + "?ttl=0";
  lcm::LCM bus(url);
  ASSERT_TRUE(bus.good()) << url;
  Receiver r;
  bus.subscribe("IGMS_HEARTBEAT", &Receiver::on, &r);
  igms::heartbeat_t msg;
  msg.process = "udpm-test";
  for (int k = 0; k < 5 && r.count == 0; ++k) {
    msg.seq = k;
    ASSERT_EQ(bus.publish("IGMS_HEARTBEAT", &msg), 0);
    bus.handleTimeout(200);
  }
  EXPECT_GE(r.count, 1);
  EXPECT_GE(r.seq, 0);
}

}  // namespace
