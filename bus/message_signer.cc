#include "bus/message_signer.h"

#include <openssl/rand.h>

#include <atomic>
#include <cstring>
#include <stdexcept>

namespace igms::bus {
namespace {

std::atomic<uint64_t> g_counter{0};

}  // namespace

const SenderId& processSender() {
  static const SenderId id = [] {
    SenderId s{};
    if (RAND_bytes(s.data(), static_cast<int>(s.size())) != 1) throw std::runtime_error("OpenSSL: no random bytes");
    return s;
  }();
  return id;
}

MessageSigner::MessageSigner(const BusKey& key) {
  SenderKeys keys(key);
  if (!mac_.key(keys, processSender())) throw std::runtime_error("OpenSSL: cannot key AES-256-GCM");
}

size_t MessageSigner::sign(std::string_view channel, uint8_t* buffer, size_t size) {
  const uint64_t counter = g_counter.fetch_add(1, std::memory_order_relaxed) + 1;
  uint8_t* t = buffer + size;
  std::memcpy(t, kMagic, sizeof kMagic);
  std::memcpy(t + sizeof kMagic, processSender().data(), kSenderBytes);
  uint8_t* c = t + sizeof kMagic + kSenderBytes;
  for (size_t i = 0; i < kCounterBytes; ++i) c[i] = static_cast<uint8_t>(counter >> (8 * (kCounterBytes - 1 - i)));
  const auto time = static_cast<uint64_t>(wallClockMicros());
  uint8_t* w = c + kCounterBytes;
  for (size_t i = 0; i < kTimeBytes; ++i) w[i] = static_cast<uint8_t>(time >> (8 * (kTimeBytes - 1 - i)));
  const size_t signed_size = size + kTrailerBytes;
  if (!mac_.compute(channel, buffer, signed_size, counter, buffer + signed_size - kTagBytes))
    std::memset(buffer + signed_size - kTagBytes, 0, kTagBytes);  // refused by every receiver, never a valid tag
  return signed_size;
}

}  // namespace igms::bus
