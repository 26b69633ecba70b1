// Signs messages as this process: one sender id (16 random bytes drawn at
// start) and one counter for the whole process, shared by every signer in it,
// so a receiver's per-sender replay window sees one stream per channel. One
// signer per publishing thread (each holds its own OpenSSL context); signing
// allocates nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "bus/bus_key.h"
#include "bus/message_signature.h"

namespace igms::bus {

// This process's sender id (drawn on first use).
const SenderId& processSender();

class MessageSigner {
 public:
  explicit MessageSigner(const BusKey& key);
  // `buffer` holds the payload in [0, size) and room for kTrailerBytes more:
  // appends the trailer and returns the signed size.
  size_t sign(std::string_view channel, uint8_t* buffer, size_t size);

 private:
  SenderMac mac_;
};

}  // namespace igms::bus
