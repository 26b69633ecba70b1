// A signed message written out from the trailer's description in
// bus/message_signature.h, not by MessageSigner: a second reading of the
// format, and any sender, counter and time a test needs (a replay's when
// `replayed`). Shared by signed_bus_test and bus_vectors_test.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bus/message_signature.h"

namespace igms::bus::test {

inline std::vector<uint8_t> signedAs(const BusKey& key, const SenderId& sender, uint64_t counter, int64_t time_us,
                                     const std::string& channel, std::vector<uint8_t> payload, bool replayed = false) {
  auto put = [&](uint64_t v) {
    for (int i = 7; i >= 0; --i) payload.push_back(static_cast<uint8_t>(v >> (8 * i)));
  };
  const char* magic = replayed ? kReplayMagic : kMagic;
  payload.insert(payload.end(), magic, magic + 4);
  payload.insert(payload.end(), sender.begin(), sender.end());
  put(counter);
  put(static_cast<uint64_t>(time_us));
  payload.resize(payload.size() + kTagBytes);
  SenderKeys keys(key);
  SenderMac mac;
  EXPECT_TRUE(mac.key(keys, sender, replayed));
  EXPECT_TRUE(mac.compute(channel, payload.data(), payload.size(), counter, payload.data() + payload.size() - kTagBytes));
  return payload;
}

// Sender k: its low byte, its next byte, then zeros (as tests/data/bus_vectors.json says).
inline SenderId senderOf(int k) {
  SenderId s{};
  s[0] = static_cast<uint8_t>(k & 255);
  s[1] = static_cast<uint8_t>((k >> 8) & 255);
  return s;
}

}  // namespace igms::bus::test
