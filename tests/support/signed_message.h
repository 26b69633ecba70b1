// A test's bus key and a message signed with MessageSigner, for the tests of
// the signed bus's parts (signed_bus_test, bus_subscription_test).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bus/bus_key.h"
#include "bus/message_signer.h"

namespace igms::bus::test {

// A key made from a seed (different seeds: different keys).
inline BusKey keyOf(uint8_t seed) {
  BusKey k{};
  for (size_t i = 0; i < k.size(); ++i) k[i] = static_cast<uint8_t>(seed + 7 * i);
  return k;
}

// The payload with its trailer, signed for `channel`.
inline std::vector<uint8_t> signedMessage(MessageSigner& signer, const std::string& channel,
                                          std::vector<uint8_t> payload) {
  const size_t n = payload.size();
  payload.resize(n + kTrailerBytes);
  payload.resize(signer.sign(channel, payload.data(), n));
  return payload;
}

}  // namespace igms::bus::test
