#include "bus/signed_publisher.h"

#include <cstring>

namespace igms::bus {

SignedPublisher::SignedPublisher(lcm::LCM& lcm, const std::optional<BusKey>& key, size_t reserve, SenderKind kind)
    : lcm_(lcm) {
  if (key) signer_ = std::make_unique<MessageSigner>(*key, kind);
  buffer_.resize(reserve + kTrailerBytes);
}

void SignedPublisher::grow(size_t payload) {
  if (buffer_.size() < payload + kTrailerBytes) buffer_.resize(payload + kTrailerBytes);
}

int SignedPublisher::publish(const std::string& channel, const void* data, size_t size) {
  grow(size);
  if (size) std::memcpy(buffer_.data(), data, size);
  return send(channel, size);
}

int SignedPublisher::send(const std::string& channel, size_t size) { return publishInPlace(channel, buffer_.data(), size); }

int SignedPublisher::publishInPlace(const std::string& channel, uint8_t* buffer, size_t size) {
  if (signer_) size = signer_->sign(channel, buffer, size);
  return lcm_.publish(channel, buffer, static_cast<unsigned>(size));
}

}  // namespace igms::bus
