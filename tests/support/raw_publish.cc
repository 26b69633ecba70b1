// raw_publish: publishes a log's events on one channel byte for byte, the
// recorded signature kept: an attacker who captured signed datagrams and
// sends them again (tests/integration/replay_attack_test.sh).
//   raw_publish LOG CHANNEL URL
#include <cstdio>
#include <lcm/lcm-cpp.hpp>
#include <string>

#include "tools/eventlog/event_log.h"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: raw_publish LOG CHANNEL URL\n");
    return 2;
  }
  const igms::log::LogContents log = igms::log::readAll(argv[1]);
  lcm::LCM bus(argv[3]);
  if (!bus.good()) return 2;
  int sent = 0;
  for (const igms::log::Event& e : log.events)
    if (e.channel == argv[2] && bus.publish(e.channel, e.data.data(), static_cast<unsigned>(e.data.size())) == 0) ++sent;
  std::printf("%d\n", sent);
  return sent > 0 ? 0 : 1;
}
