// Signs messages as this process: one sender id (16 random bytes drawn at
// start) and one counter for the whole process, shared by every signer in it,
// so a receiver's per-sender replay window sees one stream per channel. A
// forked child draws its own id and starts its own counter (a child signing
// under its parent's would repeat GMAC nonces); a signer it inherited keys
// itself for the child's id at its next message. One signer per publishing
// thread (each holds its own OpenSSL context); signing allocates nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "bus/bus_key.h"
#include "bus/message_signature.h"

namespace igms::bus {

// This process's sender id (drawn on first use; drawn again in a forked child).
const SenderId& processSender();

// What a signer's messages are: live traffic, or a replay of recorded traffic
// (igms-replay play: its own magic and key label, message_signature.h).
enum class SenderKind { kLive, kReplay };

class MessageSigner {
 public:
  explicit MessageSigner(const BusKey& key, SenderKind kind = SenderKind::kLive);
  // `buffer` holds the payload in [0, size) and room for kTrailerBytes more:
  // appends the trailer and returns the signed size.
  size_t sign(std::string_view channel, uint8_t* buffer, size_t size);
  // Whether it has keyed itself again for a forked child's sender.
  bool rekeyed() const { return rekeyed_; }

 private:
  SenderKeys keys_;
  SenderMac mac_;
  SenderKind kind_;
  uint64_t generation_ = 0;  // the process sender's it is keyed for
  bool rekeyed_ = false;
};

}  // namespace igms::bus
