// Publishes on LCM as this process: each message is copied into a buffer of
// the publisher's own and, with a bus key, signed (message_signer.h) before it
// goes out (or signed in the caller's own buffer: publishInPlace). Without a
// key it publishes the bytes as they are. One publisher per publishing
// thread; after the first message of the largest size it allocates nothing.
#pragma once

#include <lcm/lcm-cpp.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bus/bus_key.h"
#include "bus/message_signer.h"

namespace igms::bus {

class SignedPublisher {
 public:
  SignedPublisher(lcm::LCM& lcm, const std::optional<BusKey>& key, size_t reserve = 64 * 1024,
                  SenderKind kind = SenderKind::kLive);
  // 0 on success, like lcm::LCM::publish.
  int publish(const std::string& channel, const void* data, size_t size);
  // The same without the copy: `buffer` holds the payload in [0, size) and kTrailerBytes more room
  // (a caller's preallocated encoding buffer), signed where it is.
  int publishInPlace(const std::string& channel, uint8_t* buffer, size_t size);
  template <typename Message>
  int publish(const std::string& channel, const Message& m) {
    const size_t size = static_cast<size_t>(m.getEncodedSize());
    grow(size);
    if (m.encode(buffer_.data(), 0, static_cast<int>(size)) < 0) return -1;
    return send(channel, size);
  }
  bool keyed() const { return signer_ != nullptr; }
  lcm::LCM& lcm() { return lcm_; }

 private:
  void grow(size_t payload);
  int send(const std::string& channel, size_t size);

  lcm::LCM& lcm_;
  std::unique_ptr<MessageSigner> signer_;
  std::vector<uint8_t> buffer_;
};

}  // namespace igms::bus
