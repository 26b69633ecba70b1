#include "bus/message_signer.h"

#include <openssl/rand.h>
#include <pthread.h>

#include <atomic>
#include <cstring>
#include <mutex>
#include <stdexcept>

namespace igms::bus {
namespace {

// The process's sender: its id, its one counter, and a generation that a fork's child moves on. A
// child inherits its parent's id and counter; signing on with them would repeat (subkey, nonce) pairs,
// which GMAC must never do (two tags under one nonce give away its authentication key). So the child
// draws a new id and starts its counter again, before it runs anything else.
SenderId g_sender{};
std::atomic<uint64_t> g_counter{0};
std::atomic<uint64_t> g_generation{0};
std::atomic<bool> g_sender_ok{false};
std::once_flag g_drawn;

void redrawInChild() {
  // OpenSSL reseeds its generator in a forked child (its fork detection) before this draws.
  g_sender_ok.store(RAND_bytes(g_sender.data(), static_cast<int>(g_sender.size())) == 1);
  g_counter.store(0);
  g_generation.fetch_add(1);
}

}  // namespace

const SenderId& processSender() {
  std::call_once(g_drawn, [] {
    if (RAND_bytes(g_sender.data(), static_cast<int>(g_sender.size())) != 1)
      throw std::runtime_error("OpenSSL: no random bytes");
    g_sender_ok.store(true);
    pthread_atfork(nullptr, nullptr, redrawInChild);
  });
  return g_sender;
}

MessageSigner::MessageSigner(const BusKey& key, SenderKind kind) : keys_(key), kind_(kind) {
  generation_ = g_generation.load();
  if (!mac_.key(keys_, processSender(), kind_ == SenderKind::kReplay)) throw std::runtime_error("OpenSSL: cannot key AES-256-GCM");
}

size_t MessageSigner::sign(std::string_view channel, uint8_t* buffer, size_t size) {
  const SenderId& sender = processSender();
  bool keyed = g_sender_ok.load();
  if (generation_ != g_generation.load()) {  // forked since: the new sender's subkey
    generation_ = g_generation.load();
    keyed = keyed && mac_.key(keys_, sender, kind_ == SenderKind::kReplay);
    rekeyed_ = keyed;
  }
  const uint64_t counter = g_counter.fetch_add(1, std::memory_order_relaxed) + 1;
  uint8_t* t = buffer + size;
  std::memcpy(t, kind_ == SenderKind::kReplay ? kReplayMagic : kMagic, sizeof kMagic);
  std::memcpy(t + sizeof kMagic, sender.data(), kSenderBytes);
  uint8_t* c = t + sizeof kMagic + kSenderBytes;
  for (size_t i = 0; i < kCounterBytes; ++i) c[i] = static_cast<uint8_t>(counter >> (8 * (kCounterBytes - 1 - i)));
  const auto time = static_cast<uint64_t>(wallClockMicros());
  uint8_t* w = c + kCounterBytes;
  for (size_t i = 0; i < kTimeBytes; ++i) w[i] = static_cast<uint8_t>(time >> (8 * (kTimeBytes - 1 - i)));
  const size_t signed_size = size + kTrailerBytes;
  if (!keyed || (generation_ != g_generation.load()) ||
      !mac_.compute(channel, buffer, signed_size, counter, buffer + signed_size - kTagBytes))
    std::memset(buffer + signed_size - kTagBytes, 0, kTagBytes);  // refused by every receiver, never a valid tag
  return signed_size;
}

}  // namespace igms::bus
